"""The one rule for relative tolerances, for every path (CasADi, the
compiled backend, sweeps, trajectory functions, the FMU's solver.rtol and
experiment tolerance): below RTOL_MIN double precision cannot follow, above
RTOL_MAX an error test passes answers wrong by orders of magnitude (rtol 1
gave 3.7e9 Pa for a 9.2e7 Pa peak)."""
from __future__ import annotations

import math

from pdbfs.errors import ParameterError

RTOL_MIN, RTOL_MAX = 1e-15, 0.1


def check_rtol(rtol, where: str = "rtol") -> float:
    """``rtol`` as a float, or a ParameterError naming the allowed range."""
    try:
        v = float(rtol)
    except (TypeError, ValueError):
        raise ParameterError(f"{where} = {rtol!r}: must be a number") from None
    if not (math.isfinite(v) and RTOL_MIN <= v <= RTOL_MAX):
        raise ParameterError(f"{where} = {v:g}: must be in [{RTOL_MIN:g}, {RTOL_MAX:g}] (a "
                             "relative tolerance above that cannot give a meaningful answer)"
                             if math.isfinite(v) and v > RTOL_MAX else
                             f"{where} = {v:g}: must be in [{RTOL_MIN:g}, {RTOL_MAX:g}]")
    return v
