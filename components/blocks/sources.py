"""Signal sources: functions of time with an output ``y`` (after
Modelica.Blocks.Sources). Every switch or kink of a source is a time event,
so that no integrator step jumps over it. Before its ``start_time`` a source
gives its ``offset``; at the start time itself it already gives the value
after the switch."""
from __future__ import annotations

import math

import casadi as ca

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, eq, time

from .interfaces import SO


class Constant(SO):
    """A constant output ``y = k``.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    def declare(self):
        super().declare()
        self.k = self.signal_parameter(1.0, "Constant output value")

    def equations(self):
        return [eq(self.y.value, self.k)]


class PartialSource(SO):
    """A source that starts at ``start_time`` on top of an ``offset``:
    ``y = offset + signal()``, where ``signal()`` is zero before the start.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    start_time = Parameter(0.0, "s", "Time at which the signal starts", min=0.0)

    def declare(self):
        super().declare()
        self.offset = self.signal_parameter(0.0, "Value of the output before the start time "
                                            "(and added after it)")

    def signal(self):
        """The part of ``y`` above the offset (a CasADi expression of time)."""
        raise NotImplementedError

    def equations(self):
        return [eq(self.y.value, self.offset + self.signal())]


class Step(PartialSource):
    """A step of ``height`` at ``start_time``: ``y = offset`` before it,
    ``offset + height`` from it on (a time event).

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    def declare(self):
        super().declare()
        self.height = self.signal_parameter(1.0, "Height of the step")

    def signal(self):
        return ca.if_else(time >= self.start_time, self.height, 0.0)

    def time_events(self):
        return [(self.start_time, "step", "the step (time = start_time)")]


class Ramp(PartialSource):
    """A ramp rising by ``height`` over ``duration`` from ``start_time``,
    then held: ``y = offset + height*min(max((t - start_time)/duration, 0),
    1)``. Both kinks are time events.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    duration = Parameter(1.0, "s", "Time the ramp takes to rise by its height", positive=True)

    def declare(self):
        super().declare()
        self.height = self.signal_parameter(1.0, "Rise of the ramp")

    def signal(self):
        x = (time - self.start_time) / self.duration
        return self.height * ca.fmin(ca.fmax(x, 0.0), 1.0)

    def time_events(self):
        return [(self.start_time, "ramp_start", "the ramp starts (time = start_time)"),
                (self.start_time + self.duration, "ramp_end",
                 "the ramp ends (time = start_time + duration)")]


class Sine(PartialSource):
    """A sine wave from ``start_time`` on: ``y = offset + amplitude*sin(2*pi*f*(t
    - start_time) + phase)``, ``offset`` before (a time event: the output
    jumps there unless ``phase`` is a multiple of pi).

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    f = Parameter(1.0, "Hz", "Frequency", min=0.0)
    phase = Parameter(0.0, "rad", "Phase at the start time")

    def declare(self):
        super().declare()
        self.amplitude = self.signal_parameter(1.0, "Amplitude of the sine")

    def signal(self):
        wave = self.amplitude * ca.sin(2.0 * math.pi * self.f * (time - self.start_time)
                                       + self.phase)
        return ca.if_else(time >= self.start_time, wave, 0.0)

    def time_events(self):
        return [(self.start_time, "sine_start", "the sine starts (time = start_time)")]


class Pulse(PartialSource):
    """A train of ``periods`` rectangular pulses: from ``start_time`` on,
    every ``period`` seconds the output rises by ``amplitude`` for ``width``
    seconds, ``y = offset + amplitude`` then, ``y = offset`` between. Each
    rise and fall is a time event.

    ``periods`` (a whole number >= 1, a constructor argument: 100 by
    default) bounds the train: after the last period the output stays at
    ``offset``. Give as many periods as the run needs (``t_end/period``).
    The bound is there because each switch is an event indicator of the
    rig and a term of the output, evaluated at every solver step, so a
    run's cost grows with the square of the periods: a mass pushed by 100
    pulses runs in 0.1 s compiled (2 s with CasADi, which restarts at each
    switch), by 1000 pulses in 9 s (2 minutes). A long train is better
    driven by an input of the rig.

    Parameters
    ----------
    periods : int
        The number of pulses (>= 1).
    unit : str
        The unit of its output (SI text; "1" for a plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), ``amplitude`` and ``offset`` in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For ``periods`` that is not a whole number >= 1, or a unit that is
        not a unit's text.
    """

    width = Parameter(0.5, "s", "Time the output stays high in each period", positive=True)
    period = Parameter(1.0, "s", "Time from one rise to the next", positive=True)

    def __init__(self, periods: int = 100, unit: str = "1", **params):
        if isinstance(periods, bool) or not isinstance(periods, int) or periods < 1:
            raise ParameterError(f"Pulse: periods = {periods!r} must be a whole number >= 1")
        self._periods = periods
        super().__init__(unit=unit, **params)

    def declare(self):
        super().declare()
        self.amplitude = self.signal_parameter(1.0, "Height of each pulse above the offset")

    def _edges(self):
        """(rise, fall) times of each pulse, as the time events state them."""
        return [(self.start_time + k * self.period, self.start_time + k * self.period + self.width)
                for k in range(self._periods)]

    def signal(self):
        # the same expressions as the time events: at a switch time the new
        # value holds exactly, where the integrator restarts
        high = sum(ca.if_else(time >= rise, 1.0, 0.0) - ca.if_else(time >= fall, 1.0, 0.0)
                   for rise, fall in self._edges())
        return self.amplitude * high

    def conditions(self):
        return [(self.period - self.width, "a pulse would be longer than its period",
                 ["width", "period"])]

    def time_events(self):
        out = []
        for k, (rise, fall) in enumerate(self._edges()):
            out += [(rise, f"rise_{k + 1}", f"pulse {k + 1} rises"),
                    (fall, f"fall_{k + 1}", f"pulse {k + 1} falls")]
        return out
