"""Boundary conditions: a tank, prescribed pressure (a parameter, a function
of time or a signal) and prescribed flow."""
from pdbfs.modelling import Parameter, SignalInput, Variable, eq, switch_times, time

from .interfaces import PartialOnePort
from .laws import ATMOSPHERE


class PartialSource(PartialOnePort):
    """A source whose value is a parameter, or ``function(t)`` giving a
    CasADi expression of time (which may use the component's parameters).
    ``breakpoints``: the times (numbers or parameter expressions) at which
    ``function`` switches; every integrator stops there.

    Connector: ``port``.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the value, in the parameter's unit, as a CasADi
        expression of time (it may use the component's parameters); None:
        the parameter.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters, SI units.
    """

    def __init__(self, function=None, breakpoints=(), **params):
        self._function = function
        self._breakpoints = breakpoints
        super().__init__(**params)

    def time_events(self):
        return switch_times(self, self._breakpoints)

    def prescribed(self, constant):
        """The source's value: its parameter, or ``function(t)`` when given.

        Parameters
        ----------
        constant : casadi.SX
            The source's parameter (``self.p``, ``self.Q``).

        Returns
        -------
        casadi.SX
            ``constant``, or ``function(time)``.
        """
        return constant if self._function is None else self._function(time)


class PressureSource(PartialSource):
    """A prescribed pressure at ``port``, ``port.p = p``: the parameter ``p``
    or ``function(t)``. ``q_out = -port.q`` is the flow it delivers.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the value, in the parameter's unit, as a CasADi
        expression of time (it may use the component's parameters); None:
        the parameter.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters, SI units.
    """

    pressure_bound = {"sources": ("port.p",)}    # (modelling.pressure_bound)

    closable = True
    p = Parameter(10e6, "Pa", "Pressure (absolute)", min=0.0)

    def declare(self):
        super().declare()
        self.q_out = Variable("m3/s", "Flow delivered into the circuit", output=True)

    def equations(self):
        return [eq(self.port.p, self.prescribed(self.p)), eq(self.q_out, -self.port.q)]


class Tank(PressureSource):
    """A reservoir at a fixed pressure ``p`` (atmospheric by default):
    ``port.p = p``.

    Connector: ``port``; ``q_out`` is the flow it delivers.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the value, in the parameter's unit, as a CasADi
        expression of time (it may use the component's parameters); None:
        the parameter.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters, SI units.
    """

    p = Parameter(ATMOSPHERE, "Pa", "Tank pressure (absolute)", min=0.0)


class FlowSource(PartialSource):
    """A prescribed flow ``Q`` delivered into the circuit at ``port``, or
    ``function(t)``: ``port.q = -Q``.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the value, in the parameter's unit, as a CasADi
        expression of time (it may use the component's parameters); None:
        the parameter.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters, SI units.
    """

    Q = Parameter(1e-4, "m3/s", "Flow delivered into the circuit")

    def declare(self):
        super().declare()
        self.p = Variable("Pa", "Pressure at the port", output=True)

    def equations(self):
        return [eq(self.port.q, -self.prescribed(self.Q)), eq(self.p, self.port.p)]


class SignalPressure(PartialOnePort):
    """A pressure at ``port`` given by the signal input ``u`` (Pa,
    absolute), as PressureSource prescribes its own, ``port.p = u``;
    ``q_out = -port.q`` is the flow it delivers."""

    pressure_bound = {"sources": ("port.p",)}    # (modelling.pressure_bound)

    closable = True

    def declare(self):
        super().declare()
        self.u = SignalInput("Pa", "Pressure to impose (absolute)")
        self.q_out = Variable("m3/s", "Flow delivered into the circuit", output=True)

    def equations(self):
        return [eq(self.port.p, self.u.value), eq(self.q_out, -self.port.q)]
