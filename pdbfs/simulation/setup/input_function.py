"""An input given as a function of time, made a trace before the run.

``f`` is evaluated at the output times and at FIRST + 1 even times over
the run, then every interval is halved
where ``f`` at its middle differs from the straight line between its ends
by more than CALLABLE_RTOL of the largest |f| seen, until none does: the
run then integrates that piecewise-linear trace exactly (its samples are
breakpoints). Where ``f`` is smooth the trace is within about
CALLABLE_RTOL of it everywhere (the error of a line is largest at the
middle); a jump is found within ``MIN_WIDTH`` of the run's length. A
feature narrower than the output step that leaves every middle point on
its line (a spike between two samples) is not seen: give such an input as
a trace. ``f`` is called with a numpy array of times first; where that
fails or gives no array of the same shape, one time at a time.
"""
from __future__ import annotations

import numpy as np

from pdbfs.errors import ParameterError

#: the sampled trace's largest deviation from f at an interval's middle,
#: relative to the largest |f| (absolute where f is 0 throughout)
CALLABLE_RTOL = 1e-6
#: intervals shorter than this part of the run are not halved again (a jump)
MIN_WIDTH = 1e-9
#: the first samples: the output times and this many even intervals over the run
FIRST = 1024
#: the most samples of one function
MAX_SAMPLES = 1_000_000


def sample_callable(name, f, grid):
    """(t, u): ``f`` sampled on [grid[0], grid[-1]] to CALLABLE_RTOL."""
    grid = np.asarray(grid, float)
    t = np.unique(np.concatenate([grid, np.linspace(grid[0], grid[-1], FIRST + 1)]))
    run = (float(grid[0]), float(grid[-1]))
    u = _evaluate(name, f, t, run)
    span = float(t[-1] - t[0])
    todo = np.arange(t.size - 1)           # the intervals to test
    while todo.size:
        mid = 0.5 * (t[todo] + t[todo + 1])
        um = _evaluate(name, f, mid, run)
        scale = max(float(np.max(np.abs(u))), float(np.max(np.abs(um))))
        off = np.abs(um - 0.5 * (u[todo] + u[todo + 1])) > CALLABLE_RTOL * scale
        off &= (t[todo + 1] - t[todo]) > MIN_WIDTH * span
        if not off.any():
            break
        if t.size + int(off.sum()) > MAX_SAMPLES:
            raise ParameterError(f"inputs: {name}(t) needs more than {MAX_SAMPLES} samples to be "
                                 f"followed to {CALLABLE_RTOL:g} of its largest value; give it "
                                 "as a trace (t, u)")
        at = todo[off] + 1                 # insert the middles after the intervals' starts
        t = np.insert(t, at, mid[off])
        u = np.insert(u, at, um[off])
        new = at + np.arange(at.size)      # where the inserted middles landed
        todo = np.sort(np.concatenate([new - 1, new]))   # both halves of each
    return t, u


def _evaluate(name, f, t, span):
    """f at the times ``t`` (an array), every value checked finite;
    ``span`` (t0, t1) the run's, named in a refusal (which says at what
    time f failed: never to be read as the run's length)."""
    over = f"; sampled over the run, {span[0]:.6g} .. {span[1]:.6g} s"
    try:
        with np.errstate(all="ignore"):          # a 1/t at 0 is named below, not warned
            v = np.asarray(f(t.copy()), dtype=float)
        ok = v.shape == t.shape
    except Exception:            # noqa: BLE001 -- a scalar function: one time at a time
        ok = False
    if not ok:
        v = np.empty(t.size)
        for k, tk in enumerate(t):
            try:
                with np.errstate(all="ignore"):
                    v[k] = float(f(float(tk)))
            except Exception as err:   # noqa: BLE001 -- the user's function: named, one line
                what = str(err).splitlines()[0] if str(err) else ""
                raise ParameterError(f"inputs: {name}(t) raised {type(err).__name__} at "
                                     f"t = {tk:.6g} s" + (f": {what}" if what else "") + over) \
                    from None
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        raise ParameterError(f"inputs: {name}(t) = {v[bad[0]]} at t = {t[bad[0]]:.6g} s: must be "
                             f"finite{over}")
    return v
