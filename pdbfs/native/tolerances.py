"""The one rule for relative tolerances, for every path (CasADi, the
compiled backend, sweeps, trajectory functions, the FMU's solver.rtol and
experiment tolerance): below RTOL_MIN double precision cannot follow, above
RTOL_MAX an error test passes answers wrong by orders of magnitude (rtol 1
gave 3.7e9 Pa for a 9.2e7 Pa peak).

And the absolute tolerance when none is given (default_atol): fixed at 1e-10
it capped the accuracy of small signals whatever the rtol (a 1 g hammer's
piston moves 4e-9 m: its peak stayed 7.5e-5 off at rtol 1e-14); tied to
rtol below the default rtol, tightening rtol converges on any signal (as the
FMU's atol = rtol * nominal), and the default run is unchanged."""
from __future__ import annotations

import math

from pdbfs.errors import ParameterError

RTOL_MIN, RTOL_MAX = 1e-15, 0.1
#: the default relative tolerance, and the absolute one (in each state's unit) down to it
RTOL_DEFAULT, ATOL_DEFAULT = 1e-8, 1e-10


def default_atol(rtol, atol=None) -> float:
    """``atol`` as given, or for None the absolute tolerance that goes with
    ``rtol``: ATOL_DEFAULT down to RTOL_DEFAULT, below it 1e-2 * rtol."""
    if atol is not None:
        return atol
    return ATOL_DEFAULT * min(1.0, float(rtol) / RTOL_DEFAULT)


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
