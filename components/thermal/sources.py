"""Sources: a temperature or a heat flow imposed at a port, fixed (a
parameter) or prescribed (a signal input), after Modelica.Thermal.HeatTransfer.Sources."""
from pdbfs.modelling import Component, HeatPort, Parameter, SignalInput, eq

from .interfaces import T_ROOM


class FixedTemperature(Component):
    """A port held at the temperature ``T`` whatever heat flows (a room, a
    coolant bath, a large frame): ``port.T = T``.

    Connector: ``port``.
    """

    T = Parameter(T_ROOM, "K", "Fixed temperature", positive=True)

    def declare(self):
        self.port = HeatPort(insulable=True)

    def equations(self):
        return [eq(self.port.T, self.T)]


class PrescribedTemperature(Component):
    """A port held at the temperature the signal input ``u`` gives (K):
    ``port.T = u``.

    Connectors: ``port`` and the signal input ``u``.
    """

    def declare(self):
        self.port = HeatPort(insulable=True)
        self.u = SignalInput("K", "Temperature to impose")

    def equations(self):
        return [eq(self.port.T, self.u.value)]


class FixedHeatFlow(Component):
    """A constant heat flow ``Q_flow`` into the component at ``port`` (a
    heater; negative: a cooler), whatever its temperature:
    ``port.Q_flow = -Q_flow``.

    Connector: ``port`` (must be connected).
    """

    Q_flow = Parameter(0.0, "W", "Heat flow into the connected component")

    def declare(self):
        self.port = HeatPort()

    def equations(self):
        return [eq(self.port.Q_flow, -self.Q_flow)]


class PrescribedHeatFlow(Component):
    """The heat flow the signal input ``u`` gives (W) into the component at
    ``port``: ``port.Q_flow = -u``.

    Connectors: ``port`` (must be connected) and the signal input ``u``.
    """

    def declare(self):
        self.port = HeatPort()
        self.u = SignalInput("W", "Heat flow into the connected component")

    def equations(self):
        return [eq(self.port.Q_flow, -self.u.value)]
