"""Ideal sensors: they take no force (position, speed) or pass it through
(force, pressure), and give their reading as a SignalOutput."""
from pdbfs.connectors import SignalOutput
from pdbfs.symbols import Parameter, der, eq

from .interfaces import PartialOneFlange, PartialTwoFlanges


class PositionSensor(PartialOneFlange):
    """Absolute position of a flange, output ``s`` (m)."""

    def declare(self):
        super().declare()
        self.s = SignalOutput("m", "Measured position")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.s, self.flange.s)]


class SpeedSensor(PartialOneFlange):
    """Absolute velocity of a flange, output ``v`` (m/s)."""

    def declare(self):
        super().declare()
        self.v = SignalOutput("m/s", "Measured velocity")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.v, der(self.flange.s))]


class ForceSensor(PartialTwoFlanges):
    """Force passed from flange_a to flange_b, output ``f`` (N, compression
    positive: the force flange_a's side pushes with)."""

    def declare(self):
        super().declare()
        self.f = SignalOutput("N", "Measured force (compression positive)")

    def equations(self):
        return [eq(self.flange_a.s, self.flange_b.s),
                eq(self.flange_a.f + self.flange_b.f, 0.0),
                eq(self.f, self.flange_b.f)]


class PressureSensor(ForceSensor):
    """Like ForceSensor, divided by an area: output ``p`` (Pa)."""

    A = Parameter(2.270e-2, "m2", "Area the force acts on", positive=True)

    def declare(self):
        super().declare()
        self.p = SignalOutput("Pa", "Measured pressure")

    def equations(self):
        return super().equations() + [eq(self.p * self.A, self.f)]
