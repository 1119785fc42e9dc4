"""The numbers of the fatigue classes checked: each wrong one is a
ParameterError of one line naming it, its owner and what it must be."""
from __future__ import annotations

import math

import numpy as np

from pdbfs.errors import DataError, ParameterError, plain


def positive(value, name: str, owner: str, zero: bool = False) -> float:
    """``value`` as a float, refused unless a finite number above 0 (at or
    above 0 with ``zero``)."""
    v = real(value, name, owner)
    if v < 0 or (v == 0 and not zero):
        raise ParameterError(f"{owner}: {name} = {plain(v)} must be "
                             f"{'0 or more' if zero else 'positive'}")
    return v


def real(value, name: str, owner: str) -> float:
    """``value`` as a float, refused unless a finite number."""
    if isinstance(value, bool):
        raise ParameterError(f"{owner}: {name} must be a number, not {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}: {name} must be a number, not {plain(value)}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{owner}: {name} = {plain(v)} must be a finite number")
    return v


def cycles_table(cycles, owner: str) -> tuple[np.ndarray, np.ndarray]:
    """(ranges, counts) of counted cycles (a table with columns ``range`` and
    ``count``, as rainflow() gives them), refused unless one count per range,
    each a finite number, 0 or more."""
    try:
        ranges = np.asarray(cycles["range"], dtype=float)
        counts = np.asarray(cycles["count"], dtype=float)
    except (KeyError, TypeError, IndexError, ValueError):
        raise DataError(f"{owner}: give the cycles as a table with columns 'range' and 'count' "
                        "(as rainflow() gives them)") from None
    if ranges.shape != counts.shape:
        raise DataError(f"{owner}: {ranges.size} ranges but {counts.size} counts")
    for name, v in (("ranges", ranges), ("counts", counts)):
        if not np.all(np.isfinite(v)) or np.any(v < 0):
            raise DataError(f"{owner}: the {name} must be finite numbers, 0 or more")
    return ranges, counts
