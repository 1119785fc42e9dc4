"""Parameter sweeps: one compiled rig, many parameter points.

    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [1.87, 2.73, 4.23, 5.50]})
    res = pdbfs.sweep(paper_rig(), Sample("lhs", 100_000, ranges={...}), backend="c",
                      out="lhs-sweep")                       # streamed to disk, resumable
    res = pdbfs.sweep(rig, values, client=dask.distributed.Client(...))   # on a cluster

The points come in chunks (sampling); a chunk is evaluated by a Runner
(runner): with the compiled backend one call of the C summary driver per
chunk, run in threads (ctypes releases the GIL); with the CasADi backend
point by point in forked processes; on a Dask cluster as one task per
chunk, the rig built once per worker (executors). Chunks go to memory, or
to the files of a Store (store) as they finish, so a sweep of any size
runs in bounded memory and resumes after an interruption.
"""
from __future__ import annotations

import math
import signal
import threading
import os
import sys
import time
from collections.abc import Callable, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import ParameterError, missing_extra, plain, require_extra
from pdbfs.simulation import Result, Simulator
from pdbfs.simulation.run.backends import backend_for_method
from pdbfs.simulation.run.driven import Driven
from pdbfs.simulation.setup.memory import require, run_bytes, table_bytes
from pdbfs.simulation.setup.settings import default_atol, default_rtol, mapping

from .inputs import split_inputs
from .sampling import Grid, PointSet
from .result import SweepResult
from .executors import execute
from .runner import Runner, Settings
from .store import Store, chunk_columns

if TYPE_CHECKING:
    from distributed import Client
    from numpy.typing import ArrayLike

    from pdbfs.modelling import DAE, Component

#: below this many points a sweep runs in one process
PARALLEL_MIN_POINTS = 8
#: a progress bar appears once a sweep has run this long, s
PROGRESS_AFTER = 2.0
#: the most chunks a sweep is cut into by default (a billion points: 10,000 per chunk)
MAX_CHUNKS = 100_000


def points_of(values: dict, grid: bool = True) -> list[dict]:
    """The parameter points of a small sweep as dicts.

    Parameters
    ----------
    values : dict
        ``{parameter name: list of values}``.
    grid : bool
        The Cartesian product of the lists (True), or the lists read as
        columns of equal length (False).

    Returns
    -------
    list of dict
        One ``{name: value}`` per point, in the sweep's order.

    Examples
    --------
    >>> from pdbfs.studies import points_of
    >>> points_of({"hammer.v0": [2.0, 3.0], "oil.k": [2e8, 3e8]}, grid=False)
    [{'hammer.v0': 2.0, 'oil.k': 200000000.0}, {'hammer.v0': 3.0, 'oil.k': 300000000.0}]
    """
    g = Grid(values, zip=not grid)
    return [dict(zip(g.names, row.tolist())) for row in g.all()]


def sweep(rig: Component | DAE | str, values: Mapping[str, ArrayLike] | PointSet, *,
          grid: bool = True, trajectories: bool = False, t_end: float = 0.02,
          n_out: int = 2001, params: dict | None = None, start: dict | None = None,
          rtol: float | None = None, atol: float | None = None, method: str = "auto",
          max_step: float | None = None, backend: str = "auto", workers: int | None = None,
          progress: bool | Callable[[int, int], object] | None = None, client: Client | None = None,
          out: str | os.PathLike | None = None, format: str | None = None,
          chunk_size: int | None = None, overwrite: bool = False,
          inputs: Mapping[str, object] | None = None) -> SweepResult:
    """Simulate a rig at every point of a set of parameter values and
    summarise each run, on one compiled rig, locally or on a Dask cluster.

    A point that fails (a bad value, a solver failure) is returned with its
    parameters and the reason; the others still run. An unknown parameter
    name fails the whole sweep at once, before any point runs.

    Parameters
    ----------
    rig : Component, DAE or str
        The rig, its compiled DAE, or a name of ``pdbfs.models.RIGS``
        (``"paper"``).
    values : mapping of str to array_like, or Sample, Grid or Points
        ``{parameter name: list of values}`` (SI units), combined as
        ``grid`` says; or a point set: ``Sample("lhs" | "sobol" | "mc", n,
        ranges=..., dists=...)``, ``Grid`` or ``Points``. An input of the
        rig may be a dimension too: ``{input name: list of traces (t, u),
        numbers or functions}``, its column in the table the trace's number
        in the list.
    grid : bool
        For a mapping of values: every combination of the lists (True), or
        the lists read as columns of equal length (False).
    trajectories : bool
        Keep each point's full Result (``point.result``): for small sweeps
        held in memory (not with ``client`` or ``out``).
    t_end : float
        End time of each run, s.
    n_out : int
        Output points of each run (what ``trajectories`` keeps).
    params : dict, optional
        Parameter values, SI units, fixed for every point (none of them swept).
    start : dict, optional
        Start values by state name, as in ``simulate``.
    rtol, atol : float, optional
        Tolerances, as in ``simulate``.
    method : {"auto", "adams", "bdf", "erk"}
        As in ``simulate``; "auto" picks one method for the whole sweep, at
        the fixed point.
    max_step : float, optional
        Largest internal step, s.
    backend : {"auto", "c", "casadi"}
        As in ``simulate``: "c" runs a chunk in one call of the compiled
        summary driver, in threads.
    workers : int, optional
        Threads or processes on this machine (None: one per core for a
        sweep of 8 points or more, else one). Not with ``client``.
    progress : bool or callable, optional
        A progress bar on stderr (None: once the sweep has run 2 s), or a
        function called with (points done, points in all) after each chunk.
    client : dask.distributed.Client, optional
        Run on its cluster, one task per chunk (pdbfs's extra ``[dask]``).
    out : str or os.PathLike, optional
        A folder the chunks are written to as they finish: the sweep runs in
        bounded memory, and a rerun of the same sweep resumes; a folder
        holding another sweep is refused unless ``overwrite``.
    format : {None, "parquet", "csv"}
        The chunk files' format (only with ``out``; None: Parquet where
        pyarrow, the extra ``[parquet]``, is installed, else CSV).
    chunk_size : int, optional
        Points per chunk (default: up to 512 with the compiled backend, 32
        through CasADi, fewer for a small sweep).
    overwrite : bool
        Replace a folder ``out`` that holds another sweep.
    inputs : mapping of str to trace, number or callable, optional
        The rig's inputs at every point, as in ``simulate``.

    Returns
    -------
    SweepResult
        The points in input order, each with its parameters and summary or
        the reason it failed.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown name, a value refused for every point, settings that
        contradict each other, or a sweep too big to hold in memory without
        ``out``: before any point runs.

    Examples
    --------
    Three impact speeds (m/s) of the paper's rig:

    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 2.73, 3.5]})
    >>> [f"{p / 1e6:.3g} MPa" for p in res.values("peak_pressure")]
    ['67.8 MPa', '92.1 MPa', '118 MPa']

    Every combination of two parameters, and a Latin hypercube of 8 points:

    >>> res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5], "oil.k": [2e8, 3e8]})
    >>> len(res.points), res.n_failed
    (4, 0)
    >>> from pdbfs.studies import Sample
    >>> lhs = Sample("lhs", 8, ranges={"hammer.v0": (2.0, 3.5), "seal.c": (1e4, 4e4)})
    >>> pdbfs.sweep(paper_rig(), lhs).values("pulse_duration").shape
    (8,)
    """
    if out is None and (format is not None or overwrite):
        raise ParameterError("sweep: " + ("format=" if format is not None else "overwrite=")
                             + " is about the chunk files in out=; without out= the sweep is "
                             "held in memory and writes none")
    if client is not None and workers is not None:
        raise ParameterError(f"sweep: workers = {plain(workers)} is for this machine; with "
                             "client= the cluster's workers run the sweep")
    if format is None:
        format = "csv" if missing_extra("parquet") else "parquet"
    elif format == "parquet" and out is not None:
        require_extra("parquet", "sweep files in Parquet (format='parquet', --format parquet)")
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        rig = RIGS[rig]()
    sim = Simulator.of(rig)
    values, swept_inputs = split_inputs(sim, values, inputs, t_end, n_out)
    points = values if isinstance(values, PointSet) else Grid(values, zip=not grid)
    fixed = mapping(params, "params")
    clash = sorted(set(fixed) & set(points.names))
    if clash:
        raise ParameterError(f"sweep: {', '.join(clash)} is both swept and fixed in params=")
    info = {p.name: p for p in sim.dae.params}
    # names first: an unknown name is an error of the whole sweep, not of a point
    named = [n for n in points.names if swept_inputs is None or n not in swept_inputs.dims]
    sim.param_vector({n: info[n].value if n in info else 0.0 for n in named + list(fixed)})
    p_fixed = sim.param_vector(fixed)
    sim.grid(t_end, n_out)
    sim.check_settings(default_rtol(method, rtol), atol, method, max_step, backend=backend)
    asked, backend = backend, sim.resolve_backend(backend)
    x_fixed = sim.start_vector(p_fixed, start)
    # "auto": one method for the whole sweep, judged at the fixed point
    method = sim.resolve_method(method, p_fixed, x_fixed, float(t_end), backend)
    backend = backend_for_method(sim, asked, backend, method)
    rtol = default_rtol(method, rtol)
    atol = default_atol(rtol, atol)
    if trajectories and (client is not None or out is not None):
        raise ParameterError("sweep: trajectories are kept in memory only (not with client= or out=)")
    settings = Settings(float(t_end), int(n_out), float(rtol), float(atol), method, max_step,
                        backend, tuple(sorted((start or {}).items())), bool(trajectories))
    runner = Runner(sim, points.names, fixed, settings, swept_inputs)

    n = points.n
    if out is None:           # held in memory: refused now if it cannot fit, not at the end
        per = table_bytes(1, len(points.names) + len(runner.keys) + 2) + \
            (run_bytes(sim.dae, n_out) if trajectories else 0)
        require(n * per, f"sweep of rig {sim.dae.name}: {n} points in memory",
                "give out= (--out DIR) to stream them to disk")
    workers = _workers(workers, n)
    if chunk_size is None:
        per = 512 if runner.fast is not None else 32
        # at most MAX_CHUNKS chunks (files, and their list here) for any size
        chunk_size = max(1, min(per, math.ceil(n / (4 * workers))), math.ceil(n / MAX_CHUNKS))
    elif not (isinstance(chunk_size, int) and chunk_size >= 1):
        raise ParameterError(f"sweep: chunk_size = {plain(chunk_size)} must be a whole number >= 1")
    chunks = [(c, c * chunk_size, min(n, (c + 1) * chunk_size)) for c in range(math.ceil(n / chunk_size))]
    store = None
    if out is not None:
        spec = {"rig": sim.dae.name, "dae": _dae_key(sim), "points": points.spec, "fixed": fixed,
                "settings": settings.__dict__}
        if swept_inputs is not None:         # a rerun with other traces is another sweep
            spec["inputs"] = swept_inputs.key()
        store = Store(out, spec, n, chunk_size, format or "parquet", overwrite)
        done = store.done()
        chunks = [c for c in chunks if c[0] not in done]

    t0 = time.perf_counter()
    bar = _bar(n, n - sum(b - a for _, a, b in chunks), progress, sim.dae.name)
    kept, results = [], {}

    def save(cid, chunk):
        if store is not None:
            store.write(cid, chunk_columns(chunk, points.names, runner.keys))
        else:
            kept.append(chunk_columns(chunk, points.names, runner.keys))
            for i, r in zip(chunk.index, chunk.results):
                if r is not None:
                    results[int(i)] = _rebuild(sim, r)
        bar.update(len(chunk.index))

    with deferred_interrupt(store is not None) as stop:
        def finish(cid, chunk):
            save(cid, chunk)
            if stop:                # Ctrl-C: once this chunk is saved, not inside a solver
                raise KeyboardInterrupt
        try:
            where, workers = execute(client, sim, points, fixed, settings, chunks, finish,
                                      runner, workers)
        finally:
            bar.close()
    columns = _columns(kept) if store is None else None
    res = SweepResult(sim.dae.name, points.names, runner.keys, columns=columns, store=store,
                      results=results, elapsed=time.perf_counter() - t0, workers=workers,
                      where=where)
    res.computed = sum(b - a for _, a, b in chunks)   # the others were on disk already
    return res


def _columns(kept) -> dict:
    """The chunks' columns joined, in point order (one table: a frame per
    chunk cost a tenth of a fast sweep)."""
    cols = {}
    for name in kept[0]:
        parts = [c[name] for c in kept]
        cols[name] = np.concatenate(parts) if isinstance(parts[0], np.ndarray) else \
            [v for part in parts for v in part]
    order = np.argsort(cols["point"], kind="stable")
    return {k: v[order] if isinstance(v, np.ndarray) else [v[i] for i in order]
            for k, v in cols.items()}


@contextmanager
def deferred_interrupt(defer: bool = True):
    """Ctrl-C held until the chunk at hand is finished and saved: CasADi's
    solvers check for it in the middle of a step and would swallow it. Yields
    a list that is non-empty once Ctrl-C came (main thread only). With nothing
    to save (``defer`` False: a sweep in memory) Ctrl-C stops at once."""
    hit = []
    if not defer or threading.current_thread() is not threading.main_thread():
        yield hit
        return
    old = signal.signal(signal.SIGINT, lambda signum, frame: hit.append(signum))
    try:
        yield hit
    finally:
        signal.signal(signal.SIGINT, old)


def _workers(workers, n) -> int:
    if workers is None:
        cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
        return 1 if n < PARALLEL_MIN_POINTS or (cpus or 1) < 2 else min(cpus, n)
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ParameterError(f"sweep: workers = {plain(workers)} must be a whole number >= 1")
    return min(workers, max(n, 1))


def _dae_key(sim) -> str:
    """What identifies the rig's equations, for the sweep's manifest."""
    import hashlib
    dae = sim.dae
    text = "\n".join([str(dae.ode), str(dae.y), str(dae.x0), str(dae.events), ",".join(dae.p_names)])
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _rebuild(sim, state):
    if isinstance(state, Result):
        return state
    drive = state.get("_drive")          # a run with inputs reads through them (driven.py)
    return Result.attach(sim if drive is None else Driven(sim, drive), state)


class _Report:
    """progress as a function (done, total) instead of a bar."""

    def __init__(self, fn, total, initial):
        self.fn, self.total, self.done = fn, total, initial

    def update(self, n):
        self.done += n
        self.fn(self.done, self.total)

    def close(self):
        pass


def _bar(total, initial, progress, label):
    if callable(progress):
        return _Report(progress, total, initial)
    if progress is False or (progress is None and not sys.stderr.isatty()):
        return _Report(lambda done, total: None, total, initial)     # no bar: no tqdm either
    from tqdm import tqdm
    return tqdm(total=total, initial=initial, desc=f"sweep {label}", unit="pt", file=sys.stderr,
                leave=False, delay=0 if progress else PROGRESS_AFTER)
