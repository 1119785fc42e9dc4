"""Partial bases of the thermal components (after Modelica.Thermal.HeatTransfer.Interfaces
and the conditional heat port of Modelica's dissipative components)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from pdbfs.errors import ParameterError
from pdbfs.modelling import Component, HeatPort, Parameter, Variable, eq

if TYPE_CHECKING:
    import casadi as ca

#: the reference temperature of the laws and the sources' default: 20 degC, K
T_ROOM = 293.15


class PartialElement1D(Component):
    """Heat passing from ``port_a`` to ``port_b`` through an element that stores
    none: ``Q_flow`` (W, from a to b) and ``dT = port_a.T - port_b.T`` (K).
    A subclass adds one equation relating them.

    Connectors: ``port_a`` and ``port_b`` (insulated when left unconnected).
    """

    def declare(self):
        self.port_a = HeatPort(insulable=True)
        self.port_b = HeatPort(insulable=True)
        self.Q_flow = Variable("W", "Heat flow from port_a to port_b", output=True)
        self.dT = Variable("K", "Temperature difference port_a.T - port_b.T")

    def equations(self):
        return [eq(self.dT, self.port_a.T - self.port_b.T),
                eq(self.port_a.Q_flow, self.Q_flow),
                eq(self.port_b.Q_flow, -self.Q_flow)]


def _flag(component: str, name: str, value) -> bool:
    if not isinstance(value, bool):
        raise ParameterError(f"{component}: {name} = {value!r} must be True or False")
    return value


class PartialConditionalHeatPort(Component):
    """A component that dissipates energy, with an optional heat port (as
    Modelica's ``useHeatPort``).

    ``heat_port=True`` gives it the HeatPort ``heat_port`` and the variable
    ``loss_power`` (W): the power the component dissipates (a subclass says
    which in ``dissipated_power()``) leaves through the port,
    ``heat_port.Q_flow = -loss_power``, so that the energy the mechanics or
    the hydraulics lose is the heat the thermal network receives. Without
    it (the default) the component's equations are those it has alone.

    ``port_temperature()`` is the temperature its temperature laws read: the
    port's, or, without a port, the parameter ``T`` a law declares.

    Parameters
    ----------
    *args
        Passed on to the other bases of a subclass.
    heat_port : bool
        Give the component the heat port ``heat_port`` and the variable
        ``loss_power``.
    **params : float or casadi.SX
        Values of its declared parameters, SI units.

    Raises
    ------
    pdbfs.ParameterError
        For a ``heat_port`` that is not True or False.
    """

    #: what the heat port is, as the FMU and the results describe it
    heat_port_description = "Where the dissipated power leaves the component"

    def __init__(self, *args, heat_port: bool = False, **params: float | ca.SX):
        self._heat_port = _flag(type(self).__name__, "heat_port", heat_port)
        super().__init__(*args, **params)

    def declare(self):
        super().declare()
        if self._heat_port:
            self.heat_port = HeatPort(self.heat_port_description)
            self.loss_power = Variable("W", "Power dissipated, leaving through heat_port",
                                       output=True)

    def dissipated_power(self) -> ca.SX | float:
        """The power the component dissipates, W (>= 0)."""
        raise NotImplementedError

    def declare_temperature(self) -> None:
        """Declare what the temperature laws read: without a heat port, the
        parameter ``T`` (with one, the port's temperature). Call it from
        ``declare()`` where a law is chosen."""
        if not self._heat_port:
            self.T = Parameter(T_ROOM, "K", "Temperature the laws read (without a heat port)",
                               positive=True)

    def port_temperature(self) -> ca.SX:
        """The temperature the laws read: ``heat_port.T``, else the parameter ``T``, K."""
        return self.heat_port.T if self._heat_port else self.T

    def equations(self):
        eqs = super().equations()
        if self._heat_port:
            eqs += [eq(self.loss_power, self.dissipated_power()),
                    eq(self.heat_port.Q_flow, -self.loss_power)]
        return eqs
