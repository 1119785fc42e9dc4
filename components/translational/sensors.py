"""Ideal sensors: they take no force (position, speed) or pass it through
(force, pressure), and give their reading as a SignalOutput: under its own
name (``s``, ``v``, ``f``, ``p``) and as ``y``, the output every block
reads."""
from __future__ import annotations

from typing import TYPE_CHECKING

from pdbfs.modelling import Parameter, SignalOutput, der, eq

from .interfaces import PartialOneFlange, PartialTwoFlanges

if TYPE_CHECKING:
    import casadi as ca


class PositionSensor(PartialOneFlange):
    """Absolute position of a flange, output ``s`` (m): ``s = flange.s``.

    Connectors: ``flange`` (no force), the signal outputs ``s`` and ``y`` (the same).
    """

    def declare(self):
        super().declare()
        self.s = SignalOutput("m", "Measured position")
        self.y = SignalOutput("m", "Measured position (the same as s)")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.s.value, self.flange.s),
                eq(self.y.value, self.s.value)]


class SpeedSensor(PartialOneFlange):
    """Absolute velocity of a flange, output ``v`` (m/s): ``v = der(flange.s)``.

    Connectors: ``flange`` (no force), the signal outputs ``v`` and ``y`` (the same).
    """

    def declare(self):
        super().declare()
        self.v = SignalOutput("m/s", "Measured velocity")
        self.y = SignalOutput("m/s", "Measured velocity (the same as v)")

    def equations(self):
        return [eq(self.flange.f, 0.0), eq(self.v.value, der(self.flange.s)),
                eq(self.y.value, self.v.value)]


class ForceSensor(PartialTwoFlanges):
    """Force transmitted between flange_a and flange_b, output ``f`` (N,
    positive in tension, as ``flange_b.f`` in Modelica), also as ``y``:
    ``f = flange_b.f = -flange_a.f``, the flanges at one position."""

    def declare(self):
        super().declare()
        self.f = SignalOutput("N", "Measured force (positive in tension)")
        self.y = SignalOutput(*self.reading_unit())

    def reading_unit(self) -> tuple[str, str]:
        """(unit, description) of the output ``y``."""
        return "N", "Measured force, positive in tension (the same as f)"

    def reading(self) -> ca.SX:
        """What the output ``y`` gives."""
        return self.f.value

    def equations(self):
        return [eq(self.flange_a.s, self.flange_b.s),
                eq(self.flange_a.f + self.flange_b.f, 0.0),
                eq(self.f.value, self.flange_b.f),
                eq(self.y.value, self.reading())]


class PressureSensor(ForceSensor):
    """Like ForceSensor, as a pressure on an area: output ``p`` (Pa,
    positive in compression, ``p = -f/A``), also as ``y`` (the force is
    still ``f``).

    Connectors: ``flange_a`` and ``flange_b``, the signal outputs ``f``,
    ``p`` and ``y``.
    """

    A = Parameter(2.270e-2, "m2", "Area the force acts on", positive=True, tunable=False)

    def declare(self):
        super().declare()
        self.p = SignalOutput("Pa", "Measured pressure (positive in compression)")

    def reading_unit(self):
        return "Pa", "Measured pressure, positive in compression (the same as p)"

    def reading(self):
        return self.p.value

    def equations(self):
        return super().equations() + [eq(self.p.value * self.A, -self.f.value)]
