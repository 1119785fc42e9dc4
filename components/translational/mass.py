"""Rigid bodies and the frame."""
from pdbfs.modelling import Parameter, State, Variable, der, eq

from .interfaces import PartialOneFlange, PartialTwoFlanges


class Mass(PartialTwoFlanges):
    """A rigid body sliding along x (positive down), as a point: both flanges
    sit at its position ``s``; ``m*der(v) = flange_a.f + flange_b.f`` with
    ``der(s) = v``.

    Connectors: ``flange_a`` (its upper face) and ``flange_b`` (its lower face).
    """

    m = Parameter(1.0, "kg", "Mass of the body", positive=True, tunable=False)
    s0 = Parameter(0.0, "m", "Start position", tunable=False)
    v0 = Parameter(0.0, "m/s", "Start velocity (positive down)", tunable=False)

    def declare(self):
        super().declare()
        self.s = State("m", "Position (positive down)", start=self.s0)
        self.v = State("m/s", "Velocity (positive down)", start=self.v0)
        self.a = Variable("m/s2", "Acceleration (positive down)")

    def equations(self):
        return [eq(self.flange_a.s, self.s),
                eq(self.flange_b.s, self.s),
                eq(der(self.s), self.v),
                eq(der(self.v), self.a),
                eq(self.m * self.a, self.flange_a.f + self.flange_b.f)]


class Fixed(PartialOneFlange):
    """The frame: a flange held at position ``s0``, ``flange.s = s0``."""

    s0 = Parameter(0.0, "m", "Position of the frame", tunable=False)

    def equations(self):
        return [eq(self.flange.s, self.s0)]
