"""Sources: prescribed forces and positions (parameters, functions of time,
or signals), and gravity."""
from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from pdbfs.modelling import Parameter, SignalInput, Variable, eq, switch_times, time

from .interfaces import PartialOneFlange
from ..laws import STANDARD_GRAVITY

if TYPE_CHECKING:
    import casadi as ca


class Force(PartialOneFlange):
    """A prescribed force ``F`` pushing the attached body in +x (down),
    ``flange.f = -force`` with ``force = F``: the parameter ``F``, or
    ``function(t)`` returning a CasADi expression of time (which may use the
    component's parameters). ``breakpoints``: the times
    (numbers or parameter expressions) at which ``function`` switches; every
    integrator stops there, so that no step jumps over a switch.

    Connector: ``flange``, on the body pushed.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the force, N, as a CasADi expression of time (it
        may use the component's parameters); None: the parameter ``F``.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters (``F``), SI units.
    """

    F = Parameter(0.0, "N", "Constant force, positive down")

    def __init__(self, function: Callable[[ca.SX], ca.SX] | None = None,
                 breakpoints: Sequence | Callable[[], Sequence] = (), **params: float | ca.SX):
        self._function = function
        self._breakpoints = breakpoints
        super().__init__(**params)

    def time_events(self):
        return switch_times(self, self._breakpoints)

    def declare(self):
        super().declare()
        self.force = Variable("N", "Applied force, positive down", output=True)

    def equations(self):
        value = self.F if self._function is None else self._function(time)
        return [eq(self.force, value), eq(self.flange.f, -self.force)]


class Gravity(PartialOneFlange):
    """Weight ``m*g`` of a body, pushing down (+x): ``flange.f = -m*g``.
    Bind ``m`` to the body's mass: ``Gravity(m=rig.hammer.m)``.

    Connector: ``flange``, on the body.
    """

    m = Parameter(1.0, "kg", "Mass the weight acts on", positive=True, tunable=False)
    g = Parameter(STANDARD_GRAVITY, "m/s2", "Gravitational acceleration", min=0.0,
                  tunable=False)

    def equations(self):
        return [eq(self.flange.f, -self.m * self.g)]


class Position(PartialOneFlange):
    """A prescribed position of the attached flange, ``flange.s = s0``: the
    parameter ``s0``, or ``function(t)`` returning a CasADi expression of time. A body driven by
    it has no motion of its own left (no state). ``breakpoints``: the times
    at which ``function`` switches (as for Force).

    Connector: ``flange``, on the body moved.

    Parameters
    ----------
    function : callable, optional
        ``function(t)``: the position, m, as a CasADi expression of time (it
        may use the component's parameters); None: the parameter ``s0``.
    breakpoints : sequence or callable
        The times, s (numbers or parameter expressions, or a function
        returning them), at which ``function`` switches.
    **params : float or casadi.SX
        Values of its declared parameters (``s0``), SI units.
    """

    s0 = Parameter(0.0, "m", "Constant position, positive down")

    def __init__(self, function: Callable[[ca.SX], ca.SX] | None = None,
                 breakpoints: Sequence | Callable[[], Sequence] = (), **params: float | ca.SX):
        self._function = function
        self._breakpoints = breakpoints
        super().__init__(**params)

    def time_events(self):
        return switch_times(self, self._breakpoints)

    def equations(self):
        value = self.s0 if self._function is None else self._function(time)
        return [eq(self.flange.s, value)]


class SignalForce(PartialOneFlange):
    """A force given by the signal input ``u`` (N), pushing the attached body
    in +x (down) as Force does; ``force`` is the force applied:
    ``force = u``, ``flange.f = -force``.

    Connectors: ``flange``, on the body pushed, and the signal input ``u``.
    """

    def declare(self):
        super().declare()
        self.u = SignalInput("N", "Force to apply, positive down")
        self.force = Variable("N", "Applied force, positive down", output=True)

    def equations(self):
        return [eq(self.force, self.u.value), eq(self.flange.f, -self.force)]


class SignalPosition(PartialOneFlange):
    """The position of the attached flange given by the signal input ``u``
    (m, positive down), as Position prescribes it: ``flange.s = u``. A body driven by it has
    no motion of its own left; its velocity and acceleration are the
    signal's derivatives, which the compiler forms by differentiating the
    signal's equations: the signal must be continuous (a state of a block,
    such as a FirstOrder's or SecondOrder's output, a Ramp, a linear Table
    or trace). A run whose signal jumps there (a Step, a Pulse, a held
    Table, a trace with a time given twice) is refused, naming the source:
    the impulse a damper would pass on at the jump cannot be carried. A
    kink is fine under a damper (its force jumps, no impulse is lost);
    where a mass's acceleration needs the signal's second derivative, a
    kink is refused too (an input then cannot drive it: filter it)."""

    def declare(self):
        super().declare()
        self.u = SignalInput("m", "Position to impose, positive down")

    def equations(self):
        return [eq(self.flange.s, self.u.value)]
