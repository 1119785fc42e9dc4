"""Partial bases shared by the translational components (after the Modelica
Standard Library's Mechanics.Translational.Interfaces)."""
from pdbfs.modelling import Component, Flange, Variable, der, eq


class PartialOneFlange(Component):
    """A component with one flange, ``flange``."""

    def declare(self):
        self.flange = Flange()


class PartialTwoFlanges(Component):
    """A component with two flanges: ``flange_a`` (upper), ``flange_b`` (lower)."""

    def declare(self):
        self.flange_a = Flange()
        self.flange_b = Flange()


class PartialCompliant(PartialTwoFlanges):
    """A massless element between two flanges: relative position ``s_rel``
    and the force ``f`` it transmits (positive in tension: it pulls the
    flanges together). A subclass adds one equation for ``f``.

    Connectors: ``flange_a`` and ``flange_b``; ``s_rel = flange_b.s - flange_a.s``.
    """

    def declare(self):
        super().declare()
        self.s_rel = Variable("m", "Relative position flange_b.s - flange_a.s")
        self.f = Variable("N", "Force transmitted, positive in tension")

    def equations(self):
        return [eq(self.s_rel, self.flange_b.s - self.flange_a.s),
                eq(self.flange_b.f, self.f),
                eq(self.flange_a.f, -self.f)]


class PartialCompliantWithVelocity(PartialCompliant):
    """PartialCompliant plus the relative velocity ``v_rel``, for dissipative
    elements.

    Connectors: ``flange_a`` and ``flange_b``.
    """

    def declare(self):
        super().declare()
        self.v_rel = Variable("m/s", "Relative velocity der(flange_b.s) - der(flange_a.s)")

    def equations(self):
        return super().equations() + [
            eq(self.v_rel, der(self.flange_b.s) - der(self.flange_a.s))]


class PartialCompression(PartialCompliant):
    """A compliant element that acts when its flanges approach: compression
    ``d = -s_rel - gap`` and compressive force ``fc = -f`` (an output).

    Connectors: ``flange_a`` (upper) and ``flange_b`` (lower).
    """

    def declare(self):
        super().declare()
        self.d = Variable("m", "Compression (indentation), positive when pressed together")
        self.fc = Variable("N", "Compressive force, positive when pushing the flanges apart",
                           output=True)

    def equations(self):
        return super().equations() + [eq(self.fc, -self.f)]
