"""Rainflow counting of a history (ASTM E1049-85, section 5.4.4), by the
``rainflow`` package: the history's reversals paired into full cycles and
the residue into half cycles, each with its range and mean.

A history is the sequence of a signal's values in time order: an array, a
pair ``(t, y)``, a measured trace (anything with ``t`` and ``y``), or a
rig's Result. Of a Result, the reversals are found on its output grid and
their values located on its solution (its peaks and troughs refined between
the neighbouring output points), so that the cycles do not depend on the
output grid; a Result whose pulse is still running at its end is refused
(the cycles of part of a blow are not the blow's).
"""
from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from pdbfs.errors import DataError, ParameterError

if TYPE_CHECKING:
    import pandas as pd

COLUMNS = ("range", "mean", "count")


def rainflow(history: Any, signal: str | None = None) -> "pd.DataFrame":
    """The rainflow cycles of a history (ASTM E1049-85).

    Parameters
    ----------
    history : array_like, (t, y), trace or Result
        The signal's values in time order (any unit; the ranges and means are
        in it): a 1-D array, a pair of arrays (times in s, values), an object
        with arrays ``t`` and ``y`` (a measured trace), or a rig's Result
        (its reversals located on its solution).
    signal : str, optional
        The variable of a Result to count (default: its one variable in Pa,
        the pressure of the rigs that have one). Ignored for the others.

    Returns
    -------
    pandas.DataFrame
        One row per cycle, in the order the counting closes them: ``range``
        (peak to trough), ``mean`` (their average) and ``count`` (1.0 for a
        full cycle, 0.5 for a half cycle of the residue).

    Raises
    ------
    pdbfs.DataError
        For a history with values that are not finite numbers, or a Result
        whose pulse outlasts its run.
    pdbfs.ParameterError
        For a Result with several variables in Pa and no ``signal``, or a
        ``signal`` it does not have.

    Examples
    --------
    ASTM E1049-85's example history:

    >>> from pdbfs.fatigue import rainflow
    >>> cycles = rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2])
    >>> cycles["range"].tolist()
    [3.0, 4.0, 4.0, 8.0, 9.0, 8.0, 6.0]
    >>> cycles["count"].tolist()
    [0.5, 0.5, 1.0, 0.5, 0.5, 0.5, 0.5]
    """
    import pandas as pd
    return pd.DataFrame(dict(zip(COLUMNS, cycle_arrays(history, signal))))


def cycle_arrays(history: Any, signal: str | None = None) -> tuple[np.ndarray, ...]:
    """The rainflow cycles of a history as arrays, in the order
    :func:`rainflow` gives them, without a DataFrame's cost (a campaign
    counts one blow after another).

    Parameters
    ----------
    history : array_like, (t, y), trace or Result
        As for :func:`rainflow`.
    signal : str, optional
        The variable of a Result (default: its one variable in Pa).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        The cycles' ranges, means and counts (1.0 or 0.5).
    """
    import rainflow as counter
    y = history_values(history, signal)
    rows = [c[:3] for c in counter.extract_cycles(y.tolist())] if y.size > 1 else []
    table = np.asarray(rows, dtype=float).reshape(-1, 3)
    return table[:, 0], table[:, 1], table[:, 2]


def history_values(history: Any, signal: str | None = None) -> np.ndarray:
    """The values of a history, in time order, as rainflow counts them.

    Parameters
    ----------
    history : array_like, (t, y), trace or Result
        As for :func:`rainflow`.
    signal : str, optional
        The variable of a Result (default: its one variable in Pa).

    Returns
    -------
    numpy.ndarray
        The values (of a Result: its first and last values and its reversals,
        each located on its solution).

    Raises
    ------
    pdbfs.DataError
        For values that are not finite numbers, or a Result whose pulse
        outlasts its run.
    pdbfs.ParameterError
        For a Result whose variable to count is ambiguous or unknown.
    """
    if callable(getattr(history, "peak", None)) and hasattr(history, "t"):
        return _located_reversals(history, _signal_of(history, signal))
    if hasattr(history, "t") and hasattr(history, "y"):
        values = history.y
    elif isinstance(history, tuple) and len(history) == 2 and np.ndim(history[0]) == 1:
        t, values = history
        if np.shape(t) != np.shape(values):
            raise DataError(f"history (t, y): {np.size(t)} times but {np.size(values)} values")
    else:
        values = history
    try:
        y = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise DataError("history: give an array of numbers, a pair (t, y), a trace or a Result, "
                        f"not {type(history).__name__}") from None
    if y.ndim != 1:
        raise DataError(f"history: a 1-D sequence of values is needed, not an array of shape "
                        f"{y.shape}")
    bad = np.flatnonzero(~np.isfinite(y))
    if bad.size:
        raise DataError(f"history: value {bad[0]} is {y[bad[0]]}, not a finite number "
                        f"({bad.size} such)")
    return y


def _signal_of(res, signal) -> str:
    """The variable of Result ``res`` to count: ``signal``, or its one variable in Pa."""
    names = list(getattr(res, "names", []))
    if signal is not None:
        if signal not in names:
            raise ParameterError(f"signal {signal!r} is not a variable of rig "
                                 f"{getattr(res, 'rig', '?')}")
        return signal
    units = getattr(res, "units", {}) or {}
    pressures = [n for n in names if units.get(n) == "Pa"]
    if len(pressures) != 1:
        shown = ", ".join(pressures[:6]) + (", ..." if len(pressures) > 6 else "")
        raise ParameterError(f"rig {getattr(res, 'rig', '?')}: {len(pressures)} variables in Pa"
                             f"{' (' + shown + ')' if shown else ''}; name the one to count "
                             "(signal=...)")
    return pressures[0]


def _located_reversals(res, name: str) -> np.ndarray:
    """The first value, the reversals and the last value of ``name`` in
    Result ``res``: turning points of the output grid, each refined on the
    solution between its neighbours (the larger of the sample and the
    located value, so a refinement never loses a reversal)."""
    summary = getattr(res, "summary", None)
    if callable(summary):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            s = summary()
        if s.get("complete") is False:
            blows = s.get("impact_times") or []
            if len(blows) > 1:                 # a hammer that strikes again and again
                raise DataError(f"rig {res.rig}: blow {len(blows)} (at {blows[-1]:.4g} s) is "
                                f"cut off at t_end = {res.t[-1]:.6g} s: its cycles would be a "
                                "part of its own; end the run between two blows (t_end, --t-end)")
            raise DataError(f"rig {res.rig}: the pulse is still running at t_end = "
                            f"{res.t[-1]:.6g} s: its cycles would be a part of the blow's; "
                            "simulate longer (t_end, --t-end)")
    t = np.asarray(res.t, dtype=float)
    y = np.asarray(res[name], dtype=float)
    if y.size < 3:
        return y.copy()
    step = np.diff(y)
    moves = np.flatnonzero(step != 0.0)
    turns = moves[1:][np.sign(step[moves[1:]]) != np.sign(step[moves[:-1]])]
    out = [y[0]]
    last = len(t) - 1
    for k in turns:                          # sample k: the first after the turn's plateau
        sign = 1.0 if step[k] < 0 else -1.0  # falling after it: a peak
        _, v = res.peak(name, sign=sign, window=(t[max(k - 1, 0)], t[min(k + 1, last)]))
        out.append(max(sign * v, sign * y[k]) * sign)
    out.append(y[-1])
    return np.asarray(out, dtype=float)
