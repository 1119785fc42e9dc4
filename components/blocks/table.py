"""Table: a signal given as values at times (a measured or designed trace),
interpolated linearly or held; every breakpoint is a time event."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError
from pdbfs.modelling import eq, time

from .interfaces import SO

INTERPOLATIONS = ("linear", "hold")


class Table(SO):
    """The output ``y`` follows a table of ``values`` at ``times`` (s),
    ``y = interp(t, times, values)``:
    ``interpolation="linear"`` joins the points by straight lines (as
    numpy.interp), ``"hold"`` keeps each value until the next time (a
    staircase, the value at a breakpoint being the new one). Before the
    first time the output is the first value, after the last time the last
    value.

    ``times`` must be finite and strictly increasing, ``values`` finite and
    as many; both are fixed when the table is made (they are data, not
    parameters). Every time of the table is a time event, so the
    integrators stop at each breakpoint: a jump of a held table lands
    exactly. Each evaluation of the output, and each solver step's check of
    the events, costs in proportion to the table's length: tables of some
    hundred points run well; a long measured trace is better given as an
    input of the rig.

    Connector: the signal output ``y``.

    Parameters
    ----------
    times : array_like
        The table's times, s: finite, strictly increasing.
    values : array_like
        Its values, in ``unit``: finite, one per time.
    interpolation : {"linear", "hold"}
        Straight lines between the points, or each value held until the next time.
    unit : str
        The unit of its output (SI text; "1" for a plain number).
    **params : float or casadi.SX
        Values of its declared parameters (none of its own).

    Raises
    ------
    pdbfs.ParameterError
        For an unknown interpolation, times that do not increase strictly,
        values that are not finite or not one per time.
    """

    def __init__(self, times, values, interpolation: str = "linear", unit: str = "1", **params):
        if interpolation not in INTERPOLATIONS:
            raise ParameterError(f"Table: interpolation = {interpolation!r}; choose one of "
                                 + ", ".join(INTERPOLATIONS))
        self._times = _column("times", times)
        self._values = _column("values", values)
        if len(self._values) != len(self._times):
            raise ParameterError(f"Table: {len(self._times)} times but {len(self._values)} "
                                 "values; give one value per time")
        for i in range(1, len(self._times)):
            if not self._times[i] > self._times[i - 1]:
                raise ParameterError(f"Table: times[{i}] = {self._times[i]:.17g} s is not after "
                                     f"times[{i - 1}] = {self._times[i - 1]:.17g} s; the times "
                                     "must increase strictly")
        self._interpolation = interpolation
        super().__init__(unit=unit, **params)

    def equations(self):
        return [eq(self.y.value, table_expression(time, self._times, self._values,
                                                  self._interpolation))]

    def time_events(self):
        return [(ca.SX(t), f"breakpoint_{i + 1}", f"the table's point {i + 1} (time = {t:g} s)")
                for i, t in enumerate(self._times)]


def table_expression(t, times, values, interpolation="linear"):
    """A table's value at a time, as a CasADi expression: one piece per
    interval, only the one holding ``t`` nonzero, so that no rounding of
    other pieces enters; each linear piece computed as numpy.interp does,
    ``slope*(t - t_i) + v_i``.

    Parameters
    ----------
    t : casadi.SX or float
        The time, s.
    times : sequence of float
        The table's times, s, strictly increasing.
    values : sequence of float
        Its values, one per time.
    interpolation : {"linear", "hold"}
        Straight lines between the points, or each value held until the next time.

    Returns
    -------
    casadi.SX
        The value: the first before the first time, the last after the last.
    """
    n = len(times)
    y = ca.if_else(t < times[0], values[0], 0.0) + ca.if_else(t >= times[-1], values[-1], 0.0)
    for i in range(n - 1):
        inside = ca.logic_and(t >= times[i], t < times[i + 1])
        if interpolation == "hold":
            piece = values[i]
        else:
            slope = (values[i + 1] - values[i]) / (times[i + 1] - times[i])
            piece = slope * (t - times[i]) + values[i]
        y = y + ca.if_else(inside, piece, 0.0)
    return y


def _column(name, data) -> tuple:
    """``data`` as a tuple of finite floats (a one-line ParameterError
    naming the first culprit otherwise)."""
    if isinstance(data, (str, bytes)) or not hasattr(data, "__len__"):
        raise ParameterError(f"Table: {name} must be a sequence of numbers, not "
                             f"{type(data).__name__}")
    try:
        arr = np.asarray(data, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"Table: {name} must be numbers") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ParameterError(f"Table: {name} must be a flat sequence of at least one number, "
                             f"got shape {arr.shape}")
    for i, v in enumerate(arr):
        if not math.isfinite(v):
            raise ParameterError(f"Table: {name}[{i}] = {v}: every entry must be a finite number")
    return tuple(float(v) for v in arr)
