"""The elements of a thermal network: a lumped heat capacity, a thermal
conductor, and convection to a fluid (after Modelica.Thermal.HeatTransfer.Components)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from pdbfs.modelling import Component, HeatPort, Parameter, SignalInput, State, Variable, der, eq

from .interfaces import T_ROOM, PartialElement1D, _flag

if TYPE_CHECKING:
    import casadi as ca


class HeatCapacitor(Component):
    """A body of uniform temperature ``T`` (the state, K) storing heat:
    ``C*der(T) = port.Q_flow``. ``C`` is its mass times its specific heat.

    Connector: ``port`` (insulated when left unconnected).
    """

    C = Parameter(1.0, "J/K", "Heat capacity (mass times specific heat)", positive=True)
    T0 = Parameter(T_ROOM, "K", "Start temperature", positive=True, tunable=False)

    def declare(self):
        self.port = HeatPort(insulable=True)
        self.T = State("K", "Temperature of the body", start=self.T0)

    def equations(self):
        return [eq(self.port.T, self.T), eq(self.C * der(self.T), self.port.Q_flow)]


class ThermalConductor(PartialElement1D):
    """Heat conduction with a constant conductance ``G``:
    ``Q_flow = G*(port_a.T - port_b.T)`` (a wall of area A, thickness L and
    conductivity lambda has ``G = lambda*A/L``).

    Connectors: ``port_a`` and ``port_b``; ``Q_flow`` goes from a to b.
    """

    G = Parameter(1.0, "W/K", "Thermal conductance", min=0.0)

    def equations(self):
        return super().equations() + [eq(self.Q_flow, self.G * self.dT)]


class Convection(Component):
    """Heat a surface gives to a fluid by convection, ``Q_flow = Gc*(solid.T -
    fluid.T)``, with the convective conductance ``Gc`` (W/K: the heat transfer
    coefficient times the wetted area). ``Gc`` is a parameter (W/K, >= 0,
    default 1), or with ``use_input=True`` the signal input ``Gc`` (a flow
    that changes).

    Connectors: ``solid`` (the surface), ``fluid`` (the fluid far from it),
    and with ``use_input=True`` the signal input ``Gc``.

    Parameters
    ----------
    use_input : bool
        Take ``Gc`` from a signal input (else it is a parameter).
    **params : float or casadi.SX
        Values of its declared parameters (``Gc``), SI units.
    """

    def __init__(self, use_input: bool = False, **params: float | ca.SX):
        self._use_input = _flag("Convection", "use_input", use_input)
        super().__init__(**params)

    def declare(self):
        self.solid = HeatPort(insulable=True)
        self.fluid = HeatPort(insulable=True)
        self.Q_flow = Variable("W", "Heat flow from the solid to the fluid", output=True)
        self.dT = Variable("K", "Temperature difference solid.T - fluid.T")
        if self._use_input:
            self.Gc = SignalInput("W/K", "Convective conductance (heat transfer coefficient "
                                  "times area)")
        else:
            self.Gc = Parameter(1.0, "W/K", "Convective conductance (heat transfer "
                                "coefficient times area)", min=0.0)

    def conductance(self) -> ca.SX:
        """``Gc``: the parameter's symbol or the input's value, W/K."""
        return self.Gc.value if self._use_input else self.Gc

    def equations(self):
        return [eq(self.dT, self.solid.T - self.fluid.T),
                eq(self.solid.Q_flow, self.Q_flow),
                eq(self.fluid.Q_flow, -self.Q_flow),
                eq(self.Q_flow, self.conductance() * self.dT)]
