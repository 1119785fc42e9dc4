"""Ideal hydraulic sensors: a pressure sensor takes no flow, a flow sensor
no pressure drop; each gives its reading as a SignalOutput, under its own
name (``p``, ``q``) and as ``y``, the output every block reads."""
from pdbfs.modelling import Component, HydraulicPort, SignalOutput, eq

from .interfaces import PartialOnePort


class PressureSensor(PartialOnePort):
    """Pressure at ``port``, output ``p`` (Pa), also as ``y``: ``p = port.p``,
    ``port.q = 0``."""

    pressure_bound = {}

    def declare(self):
        super().declare()
        self.p = SignalOutput("Pa", "Measured pressure (absolute)")
        self.y = SignalOutput("Pa", "Measured pressure, absolute (the same as p)")

    def equations(self):
        return [eq(self.port.q, 0.0), eq(self.p.value, self.port.p),
                eq(self.y.value, self.p.value)]


class FlowSensor(Component):
    """Flow from ``port_a`` to ``port_b`` (no pressure drop), output ``q``
    (m3/s), also as ``y``: ``q = port_a.q = -port_b.q``, ``port_a.p = port_b.p``."""

    pressure_bound = {}

    def declare(self):
        self.port_a = HydraulicPort()
        self.port_b = HydraulicPort()
        self.q = SignalOutput("m3/s", "Measured volume flow from port_a to port_b")
        self.y = SignalOutput("m3/s", "Measured volume flow from port_a to port_b (the same "
                              "as q)")

    def equations(self):
        return [eq(self.port_a.p, self.port_b.p),
                eq(self.port_a.q + self.port_b.q, 0.0),
                eq(self.q.value, self.port_a.q),
                eq(self.y.value, self.q.value)]
