"""The numbers of the fatigue classes checked: each wrong one is a
ParameterError of one line naming it, its owner and what it must be."""
from __future__ import annotations

import math

from pdbfs.errors import ParameterError, plain


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
