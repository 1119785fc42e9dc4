"""Boundary conditions: a tank, prescribed pressure and prescribed flow."""
from pdbfs.modelling import Parameter, Variable, eq, time

from .interfaces import PartialOnePort
from .laws import ATMOSPHERE


class PressureSource(PartialOnePort):
    """A prescribed pressure at ``port``: the parameter ``p``, or
    ``function(t)`` giving a CasADi expression of time (which may use the
    component's parameters). ``q_out`` is the flow it delivers."""

    closable = True
    p = Parameter(10e6, "Pa", "Pressure (absolute)", min=0.0)

    def __init__(self, function=None, **params):
        self._function = function
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.q_out = Variable("m3/s", "Flow delivered into the circuit", output=True)

    def equations(self):
        value = self.p if self._function is None else self._function(time)
        return [eq(self.port.p, value), eq(self.q_out, -self.port.q)]


class Tank(PressureSource):
    """A reservoir at a fixed pressure ``p`` (atmospheric by default)."""

    p = Parameter(ATMOSPHERE, "Pa", "Tank pressure (absolute)", min=0.0)


class FlowSource(PartialOnePort):
    """A prescribed flow ``Q`` delivered into the circuit at ``port``, or
    ``function(t)`` (as PressureSource)."""

    Q = Parameter(1e-4, "m3/s", "Flow delivered into the circuit")

    def __init__(self, function=None, **params):
        self._function = function
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.p = Variable("Pa", "Pressure at the port", output=True)

    def equations(self):
        value = self.Q if self._function is None else self._function(time)
        return [eq(self.port.q, -value), eq(self.p, self.port.p)]
