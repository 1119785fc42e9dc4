"""Sizes that cannot fit, refused before any work: what a run or a study would
hold in memory, against what the machine has available now (psutil)."""
from __future__ import annotations

from pdbfs.errors import ParameterError

#: the share of the available memory a single request may take
SHARE = 0.8


def available() -> float:
    """Bytes of memory available now (psutil's estimate: free + reclaimable)."""
    import psutil
    return float(psutil.virtual_memory().available)


def plain_bytes(n: float) -> str:
    """``n`` bytes in kB, MB, GB or TB, three digits."""
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"


def require(nbytes: float, what: str, hint: str = "") -> None:
    """Refuse ``what`` if its ``nbytes`` do not fit in the memory available."""
    if nbytes < 1e8:                     # small: not worth asking the system
        return
    have = available()
    if nbytes > SHARE * have:
        raise ParameterError(f"{what} would need about {plain_bytes(nbytes)} of memory; "
                             f"{plain_bytes(have)} are available{'; ' + hint if hint else ''}")


def run_bytes(dae, n_points: int) -> float:
    """A run on ``n_points`` output points: the states and algebraic variables
    (CasADi's copy and numpy's), every output, and time."""
    nx, nz, ny = dae.x.numel(), dae.z.numel(), len(dae.y_names)
    return 8.0 * float(n_points) * (2 * (nx + nz) + ny + 1)


def table_bytes(n_points: int, n_columns: int) -> float:
    """A study's table of ``n_points`` rows held in memory (a pandas frame
    built from per-chunk columns, with Python lists of the points on the way)."""
    return float(n_points) * (8.0 * 3 * n_columns + 200.0)
