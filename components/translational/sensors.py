"""Ideal sensors: they take no force (position, speed) or pass it through
(force, pressure), and give their reading as a SignalOutput."""
from pdbfs.modelling import Parameter, SignalOutput, der, eq

from .interfaces import PartialOneFlange, PartialTwoFlanges


class PositionSensor(PartialOneFlange):
    """Absolute position of a flange, output ``s`` (m)."""

    def declare(self):
        super().declare()
        self.s = SignalOutput("m", "Measured position")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.s.value, self.flange.s)]


class SpeedSensor(PartialOneFlange):
    """Absolute velocity of a flange, output ``v`` (m/s)."""

    def declare(self):
        super().declare()
        self.v = SignalOutput("m/s", "Measured velocity")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.v.value, der(self.flange.s))]


class ForceSensor(PartialTwoFlanges):
    """Force transmitted between flange_a and flange_b, output ``f`` (N,
    positive in tension, as ``flange_b.f`` in Modelica)."""

    def declare(self):
        super().declare()
        self.f = SignalOutput("N", "Measured force (positive in tension)")

    def equations(self):
        return [eq(self.flange_a.s, self.flange_b.s),
                eq(self.flange_a.f + self.flange_b.f, 0.0),
                eq(self.f.value, self.flange_b.f)]


class PressureSensor(ForceSensor):
    """Like ForceSensor, as a pressure on an area: output ``p`` (Pa,
    positive in compression, ``p = -f/A``)."""

    A = Parameter(2.270e-2, "m2", "Area the force acts on", positive=True, tunable=False)

    def declare(self):
        super().declare()
        self.p = SignalOutput("Pa", "Measured pressure (positive in compression)")

    def equations(self):
        return super().equations() + [eq(self.p.value * self.A, -self.f.value)]
