"""Partial bases of the hydraulic components (after Modelica's
Fluid.Interfaces.PartialTwoPort and ModelingToolkitStandardLibrary's
hydraulic interfaces): a component with one port, and one with two ports
that passes a flow ``q`` from ``port_a`` to ``port_b`` driven by
``dp = port_a.p - port_b.p``."""
from pdbfs.modelling import Component, HydraulicPort, Variable, eq


class PartialOnePort(Component):
    """A component with one hydraulic port, ``port``. ``closable`` says
    whether the port may be left unconnected (closed, zero flow)."""

    closable = False

    def declare(self):
        self.port = HydraulicPort(closable=self.closable)


class PartialTwoPort(Component):
    """Two ports, no storage: the flow ``q`` (m3/s) enters at ``port_a`` and
    leaves at ``port_b``; ``dp = port_a.p - port_b.p``. A subclass adds one
    equation relating ``q`` and ``dp``."""

    def declare(self):
        self.port_a = HydraulicPort()
        self.port_b = HydraulicPort()
        self.dp = Variable("Pa", "Pressure difference port_a.p - port_b.p")
        self.q = Variable("m3/s", "Volume flow from port_a to port_b", output=True)

    def equations(self):
        return [eq(self.dp, self.port_a.p - self.port_b.p),
                eq(self.port_a.q, self.q),
                eq(self.port_a.q + self.port_b.q, 0.0)]
