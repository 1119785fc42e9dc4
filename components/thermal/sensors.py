"""Ideal sensors: the temperature at a port (taking no heat), the heat flow
through a point of the network (no temperature drop), each as the signal
output ``y``."""
from pdbfs.modelling import Component, HeatPort, SignalOutput, eq


class TemperatureSensor(Component):
    """The temperature of a port, output ``y`` (K), taking no heat:
    ``y = port.T``, ``port.Q_flow = 0``.

    Connectors: ``port`` (must be connected) and the signal output ``y``.
    """

    def declare(self):
        self.port = HeatPort()
        self.y = SignalOutput("K", "Measured temperature")

    def equations(self):
        return [eq(self.port.Q_flow, 0.0), eq(self.y.value, self.port.T)]


class HeatFlowSensor(Component):
    """The heat flow from ``port_a`` to ``port_b``, output ``y`` (W), put in
    series where the flow is to be measured: ``y = port_a.Q_flow``,
    ``port_a.T = port_b.T``.

    Connectors: ``port_a``, ``port_b`` and the signal output ``y``.
    """

    def declare(self):
        self.port_a = HeatPort(insulable=True)
        self.port_b = HeatPort(insulable=True)
        self.y = SignalOutput("W", "Measured heat flow from port_a to port_b")

    def equations(self):
        return [eq(self.port_a.T, self.port_b.T),
                eq(self.port_a.Q_flow + self.port_b.Q_flow, 0.0),
                eq(self.y.value, self.port_a.Q_flow)]
