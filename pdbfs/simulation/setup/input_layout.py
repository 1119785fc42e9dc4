"""A trace's one layout: the pair (t, u), times first (a tuple or list of
two sequences, or an array of shape (2, n)), or named columns (a dict or a
pandas DataFrame with a time column ``t`` or ``time`` and one value
column). Rows of (t, u) are refused with the way to give them: read as
(t, u) they would be another trace, and a wrong run."""
from __future__ import annotations

import numpy as np

from pdbfs.errors import ParameterError, plain


def columns(name, given):
    """The times and values of a trace in its one layout: the pair (t, u),
    two sequences of equal length, times first (a tuple or list of two
    lists or arrays, or an array of shape (2, n)); or named columns, a dict
    or a pandas DataFrame with a time column ``t`` or ``time`` and one value
    column (named like the input, or the only other one). Rows of (t, u) (a
    list of pairs, an array of shape (n, 2)) are refused, saying how to
    give them: read as (t, u) they would be another trace."""
    if isinstance(given, dict) or hasattr(given, "columns"):
        return _named(name, given)
    if isinstance(given, np.ndarray) and given.ndim == 2:
        if given.shape[0] != 2:
            hint = ("; for rows of (time, value) give (a[:, 0], a[:, 1])"
                    if given.shape[1] == 2 else "")
            raise ParameterError(f"inputs: {name} = an array of shape {given.shape}: give a "
                                 "trace (t, u), a row of times and a row of values (shape "
                                 f"(2, n)){hint}")
        given = (given[0], given[1])
    if not (isinstance(given, (tuple, list)) and len(given) == 2):
        if isinstance(given, (tuple, list)) and len(given) > 2 and \
                all(np.ndim(r) == 1 and np.size(r) == 2 for r in given):
            raise ParameterError(f"inputs: {name} = {shown(given)}: {len(given)} rows of "
                                 "(time, value); a trace is (t, u), the times and the values: "
                                 "give tuple(zip(*rows))")
        raise ParameterError(f"inputs: {name} = {shown(given)}: give a trace (t, u) of times "
                             "and values, a number, or a function of time")
    return _numbers(name, given[0], given[1])


def _named(name, table):
    """(t, u) of a dict or DataFrame with named columns."""
    keys = list(table.keys())
    time = [k for k in keys if isinstance(k, str) and k.strip().lower() in ("t", "time")]
    if len(time) != 1:
        raise ParameterError(f"inputs: {name}: columns {', '.join(map(plain, keys))}: name "
                             "one time column 't' or 'time' (s)")
    rest = [k for k in keys if k != time[0]]
    value = [k for k in rest if k == name or k == name.rsplit(".", 1)[-1]] or \
        (rest if len(rest) == 1 else [])
    if len(value) != 1:
        raise ParameterError(f"inputs: {name}: columns {', '.join(map(plain, keys))}: name the "
                             f"value column {name!r}, or give only it besides {time[0]!r}")
    return _numbers(name, table[time[0]], table[value[0]])


def _numbers(name, t, u):
    """Two 1-D float arrays, or the ParameterError saying what they are not."""
    try:
        t = np.asarray(t, dtype=float)
        u = np.asarray(u, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"inputs: {name}: the trace's times and values must be numbers") \
            from None
    if t.ndim != 1 or u.ndim != 1:
        raise ParameterError(f"inputs: {name}: the trace (t, u) takes two lists of numbers, "
                             f"not arrays of shapes {t.shape} and {u.shape}")
    return t, u


def shown(given) -> str:
    """``given`` as a refusal shows it: an array by its shape, else its
    first 60 characters on one line."""
    if isinstance(given, np.ndarray):
        return f"an array of shape {given.shape}"
    return " ".join(plain(given).split())[:60]
