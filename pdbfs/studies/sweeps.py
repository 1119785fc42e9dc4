"""Parameter sweeps: one compiled rig, many parameter points.

    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [1.87, 2.73, 4.23, 5.50]})
    res.to_csv("sweep.csv")
    for pt in res: print(pt.params, pt.summary or pt.error)

The rig is compiled once and every point runs on the same cached SUNDIALS
integrator (``Simulator.of(rig)``); nothing is rebuilt between points.

Parallelism: a point costs about 6 ms of integration and about 11 ms of
summary (peaks and crossings are located by root finding on the solution), so
the work is spread over forked worker processes, each running whole points
(integration and summary). CasADi's ``map(N, 'thread')`` over the integrator
was measured slower than a serial loop on this machine (6.7 vs 5.5 ms per
point, 2 cores) and would leave the summaries serial, so it is not used.
Below ``PARALLEL_MIN_POINTS`` points, or on one core, the sweep runs serially.
"""
from __future__ import annotations

import itertools
import math
import os
import sys
import time
import numpy as np

from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.simulation import Result, Simulator

from .sweep_result import SweepPoint, SweepResult

#: below this many points a sweep runs serially (forking costs ~50-100 ms)
PARALLEL_MIN_POINTS = 8
#: show a progress bar for sweeps expected to take longer than this, s
PROGRESS_AFTER = 2.0


# ------------------------------------------------------------------ the points
def points_of(values: dict, grid: bool = True) -> list[dict]:
    """The parameter points of a sweep: the Cartesian product of the lists
    (``grid=True``) or the lists read as columns of equal length."""
    if not isinstance(values, dict) or not values:
        raise ParameterError("sweep: give the values as a non-empty dict "
                             "{parameter name: list of values}")
    cols = {}
    for name, vals in values.items():
        if not isinstance(name, str):
            raise ParameterError(f"sweep: parameter name {name!r} is not a string")
        if isinstance(vals, (str, bytes)) or np.isscalar(vals):
            vals = [vals]
        vals = list(np.asarray(vals, dtype=object).ravel()) if isinstance(vals, np.ndarray) \
            else list(vals)
        if not vals:
            raise ParameterError(f"sweep: no values given for {name}")
        cols[name] = vals
    names = list(cols)
    if grid:
        return [dict(zip(names, combo)) for combo in itertools.product(*cols.values())]
    lengths = {n: len(v) for n, v in cols.items()}
    if len(set(lengths.values())) > 1:
        raise ParameterError("sweep(grid=False) needs lists of equal length, got "
                             + ", ".join(f"{n}: {k}" for n, k in lengths.items()))
    n = next(iter(lengths.values()))
    return [{name: cols[name][i] for name in names} for i in range(n)]


# ------------------------------------------------------------------ the sweep
_WORK = None   # (Simulator, run kwargs, trajectories): inherited by forked workers


def sweep(rig, values: dict, *, grid: bool = True, trajectories: bool = False,
          t_end: float = 0.02, n_out: int = 2001, params: dict | None = None,
          start: dict | None = None, rtol: float = 1e-8, atol: float = 1e-10,
          method: str = "adams", max_step: float | None = None, backend: str = "casadi",
          workers: int | None = None, progress: bool | None = None) -> SweepResult:
    """Simulate ``rig`` at every point of ``values`` and summarise each.

    rig           a Component, its compiled DAE, or a name from pdbfs.models.RIGS
    values        {parameter name: list of values}
    grid          True: every combination; False: the lists are columns of
                  equal length (point i takes the i-th value of each)
    trajectories  keep each point's full Result (``point.result``)
    params        parameters fixed for every point
    t_end, n_out, start, rtol, atol, method, max_step, backend: as in pdbfs.simulate
    workers       processes to use (None: automatic; 1: serial)
    progress      show a progress bar on stderr (None: when the sweep is
                  expected to take more than a couple of seconds)

    A point that fails (a bad value, a solver failure: any PdbfsError) is
    returned with its parameters and the reason; the others still run.
    An unknown parameter name fails the whole sweep at once.
    """
    global _WORK
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        rig = RIGS[rig]()
    sim = Simulator.of(rig)
    pts = points_of(values, grid)
    names = list(pts[0])
    fixed = dict(params or {})
    clash = sorted(set(fixed) & set(names))
    if clash:
        raise ParameterError(f"sweep: {', '.join(clash)} is both swept and fixed in params=")
    # names first: an unknown name is an error of the whole sweep, not of a point
    sim.param_vector({n: _probe_value(sim, n) for n in list(names) + list(fixed)})
    sim.param_vector(fixed)
    kwargs = dict(t_end=t_end, n_out=n_out, start=start, rtol=rtol, atol=atol, method=method,
                  max_step=max_step, backend=backend)
    sim.grid(t_end, n_out)   # bad t_end / n_out: one clear error now
    sim.check_settings(rtol, atol, method, max_step, backend=backend)
    if backend == "c":
        sim.compiled()       # built once here, inherited by forked workers
    else:
        sim.integrator(sim.grid(t_end, n_out), rtol, atol, method, max_step)

    n = len(pts)
    if workers is None:
        workers = _auto_workers(n)
    elif not (isinstance(workers, int) and workers >= 1):
        raise ParameterError(f"sweep: workers = {workers!r} must be a whole number >= 1")
    workers = min(workers, n)
    if workers > 1 and not _can_fork():
        workers = 1

    t0 = time.perf_counter()
    bar = _Progress(n, progress, sim.dae.name)
    jobs = [(i, {**fixed, **p}) for i, p in enumerate(pts)]
    raw = {}
    _WORK = (sim, kwargs, trajectories)
    try:
        if workers == 1:
            for job in jobs:
                i, out = _run_point(job)
                raw[i] = out
                bar.update(1)
        else:
            import multiprocessing as mp
            chunk = max(1, min(16, math.ceil(n / (workers * 4))))
            chunks = [jobs[k:k + chunk] for k in range(0, n, chunk)]
            with mp.get_context("fork").Pool(workers) as pool:
                for outs in pool.imap_unordered(_run_chunk, chunks):
                    for i, out in outs:
                        raw[i] = out
                    bar.update(len(outs))
    finally:
        _WORK = None
        bar.close()

    res = SweepResult(rig=sim.dae.name, names=names, elapsed=time.perf_counter() - t0,
                      workers=workers)
    for i, p in enumerate(pts):
        out = raw[i]
        pt = SweepPoint(index=i, params=dict(p))
        if out[0] == "ok":
            pt.summary = out[1]
            if trajectories:
                pt.result = _rebuild(sim, out[2])
        else:
            pt.error_type, pt.error = out[1], out[2]
        res.points.append(pt)
    return res


def _probe_value(sim, name):
    """A valid value of parameter ``name`` (its default), to check names only."""
    for info in sim.dae.params:
        if info.name == name:
            return info.value
    return 0.0   # unknown: param_vector raises with a hint


def _auto_workers(n: int) -> int:
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    if n < PARALLEL_MIN_POINTS or (cpus or 1) < 2:
        return 1
    return min(cpus, n)


def _can_fork() -> bool:
    import multiprocessing as mp
    return "fork" in mp.get_all_start_methods()


def _run_chunk(jobs):
    return [_run_point(j) for j in jobs]


def _run_point(job):
    i, params = job
    sim, kwargs, keep = _WORK
    try:
        res = sim.run(params=params, **kwargs)
        summary = res.summary()
        if keep:   # the Result without its Simulator (rebuilt in the parent's)
            state = {k: v for k, v in vars(res).items() if k != "_sim"}
            return i, ("ok", summary, state)
        return i, ("ok", summary)
    except PdbfsError as err:
        return i, ("error", type(err).__name__, str(err))
    except (ArithmeticError, ValueError, RuntimeError) as err:   # anything the summary hits
        return i, ("error", type(err).__name__, f"{err}")


def _rebuild(sim, state):
    res = Result.__new__(Result)
    res.__dict__.update(state)
    res._sim = sim
    return res


class _Progress:
    """tqdm if installed, else a one-line bar on stderr; shown only when
    asked, or (progress=None) once the sweep looks like lasting a while."""

    def __init__(self, total, progress, label):
        self.total, self.done, self.progress = total, 0, progress
        self.label = label
        self.t0 = time.perf_counter()
        self.bar = None
        self.shown = False
        if progress:
            self._open()

    def _open(self):
        self.shown = True
        try:
            from tqdm import tqdm
            self.bar = tqdm(total=self.total, initial=self.done, desc=f"sweep {self.label}",
                            unit="pt", file=sys.stderr, leave=False)
        except ImportError:
            self.bar = None

    def update(self, k):
        self.done += k
        if self.progress is None and not self.shown and self.done < self.total:
            elapsed = time.perf_counter() - self.t0
            if elapsed / self.done * self.total > PROGRESS_AFTER and sys.stderr.isatty():
                self._open()
                return
        if not self.shown:
            return
        if self.bar is not None:
            self.bar.update(k)
        else:
            w = 30
            f = int(w * self.done / self.total)
            sys.stderr.write(f"\rsweep {self.label} [{'#' * f}{'.' * (w - f)}] "
                             f"{self.done}/{self.total}")
            sys.stderr.flush()

    def close(self):
        if not self.shown:
            return
        if self.bar is not None:
            self.bar.close()
        else:
            sys.stderr.write("\n")
