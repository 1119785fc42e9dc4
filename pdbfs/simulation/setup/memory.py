"""Sizes that cannot fit, refused before any work: what a run or a study would
hold in memory, against what the machine has available now (psutil); and
the probe a compiled run's record of its steps grows within (PROBE)."""
from __future__ import annotations

import ctypes

from pdbfs.errors import ParameterError

#: the share of the available memory a single request may take
SHARE = 0.8


def available() -> float:
    """Bytes of memory available now (psutil's estimate: free + reclaimable)."""
    import psutil
    return float(psutil.virtual_memory().available)


def headroom() -> float:
    """Bytes this process may still take: the memory available, and under an
    address-space limit (RLIMIT_AS) what is left below it; -1.0 when unknown.
    Never raises (the compiled record asks it from C, c/pdbfs_record.c)."""
    try:
        have = available()
        try:
            import resource
            soft = resource.getrlimit(resource.RLIMIT_AS)[0]
            if soft != resource.RLIM_INFINITY:
                import psutil
                have = min(have, float(soft - psutil.Process().memory_info().vms))
        except (ImportError, AttributeError, ValueError, OSError):
            pass                              # no such limit here (Windows)
        return max(have, 0.0)
    except Exception:                         # noqa: BLE001 - a probe must answer
        return -1.0


#: a Ctrl-C that landed in the probe, to be raised when the compiled call returns
kept_interrupt = []


def _probe() -> float:
    # Python's SIGINT handler runs at the first Python the main thread runs: in a
    # long compiled run, this callback. Raised here, ctypes would print it as an
    # ignored exception with a traceback and the run would go on: kept instead,
    # raised by interrupted() when the call is back in Python.
    try:
        return headroom()
    except KeyboardInterrupt:
        kept_interrupt.append(True)
        return -1.0


def kept_at_probe(frame) -> bool:
    """Whether a SIGINT handler called at ``frame`` is at the probe's first
    line (before its ``try``): then the interrupt is kept, as _probe would
    keep it, and the handler must return instead of raising."""
    if frame is None or frame.f_code is not _probe.__code__:
        return False
    kept_interrupt.append(True)
    return True


def interrupted() -> None:
    """Raise the KeyboardInterrupt a compiled call's probe kept (none: nothing)."""
    if kept_interrupt:
        kept_interrupt.clear()
        raise KeyboardInterrupt


#: _probe() as a C function: a compiled run's record of its steps asks it as it
#: grows (native/c/library/pdbfs_record.c) and stops the run before the system would kill it
PROBE = ctypes.CFUNCTYPE(ctypes.c_double)(_probe)


def attach(lib) -> None:
    """Give a compiled library (ctypes) the probe its records ask."""
    lib.pdbfs_set_memory_probe.restype = None
    lib.pdbfs_set_memory_probe.argtypes = [ctypes.c_void_p]
    lib.pdbfs_set_memory_probe(ctypes.cast(PROBE, ctypes.c_void_p))


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
