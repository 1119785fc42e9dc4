"""Parameter sweeps: one compiled rig, many parameter points.

    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [1.87, 2.73, 4.23, 5.50]})
    res = pdbfs.sweep(paper_rig(), Sample("lhs", 100_000, ranges={...}), backend="c",
                      out="lhs-sweep")                       # streamed to disk, resumable
    res = pdbfs.sweep(rig, values, client=dask.distributed.Client(...))   # on a cluster

The points come in chunks (sampling.py); a chunk is evaluated by a Runner
(sweep_runner.py): with the compiled backend one call of the C summary
driver per chunk, run in threads (ctypes releases the GIL); with the CasADi
backend point by point in forked processes; on a Dask cluster as one task
per chunk, the rig built once per worker. Chunks go to memory, or to the
files of a Store (sweep_store.py) as they finish, so a sweep of any size
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
from concurrent.futures import ThreadPoolExecutor
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
from .runner import Runner, Settings, payload, run_remote
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
    """The parameter points of a small sweep as dicts: the Cartesian product
    of the lists (``grid=True``) or the lists read as columns."""
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
    """Simulate ``rig`` at every point of ``values`` and summarise each.

    rig           a Component, its compiled DAE, or a name from pdbfs.models.RIGS
    values        {parameter name: list of values}, or a PointSet (sampling.py:
                  Sample("lhs" | "sobol" | "mc", n, ranges=..., dists=...)); an
                  input of the rig may be a dimension too: {input name: list of
                  traces (t, u), numbers or functions}, its column the trace's
                  number in the list (inputs.py)
    inputs        {input name: trace, number or function}: the rig's inputs at
                  every point, as in pdbfs.simulate
    grid          dict values: every combination (True) or columns (False)
    trajectories  keep each point's full Result (``point.result``; small sweeps)
    params        parameters fixed for every point
    t_end, n_out, start, rtol, atol, method, max_step, backend: as in pdbfs.simulate
    workers       threads or processes on this machine (None: automatic)
    client        a dask.distributed.Client: one task per chunk on its cluster
    out           a folder: chunks are written there as they finish (``format``
                  "parquet" or "csv"; None: Parquet where pyarrow, the extra
                  pdbfs[parquet], is installed, else CSV) and a rerun of the same
                  sweep resumes; a folder holding another sweep is refused unless
                  ``overwrite``
    progress      a progress bar on stderr (None: once the sweep takes a while), or a
                  function called with (points done, points in all) after each chunk

    A point that fails (a bad value, a solver failure) is returned with its
    parameters and the reason; the others still run. An unknown parameter
    name fails the whole sweep at once.
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
            where, workers = _execute(client, sim, points, fixed, settings, chunks, finish,
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


def _execute(client, sim, points, fixed, settings, chunks, finish, runner, workers):
    """Every chunk through ``finish``: on Dask, threads, forked processes or here."""
    if client is not None:
        return _run_dask(client, sim, points, fixed, settings, chunks, finish,
                         runner.inputs), workers
    if workers > 1 and runner.fast is not None:
        with ThreadPoolExecutor(workers) as pool:
            submit = lambda cid, a, b: pool.submit(runner.run, np.arange(a, b), points.block(a, b))  # noqa: E731
            _windowed(chunks, submit, lambda f: f.result(), 4 * workers, finish)
        return f"{workers} threads", workers
    if workers > 1 and _can_fork():
        return _run_forked(runner, points, chunks, workers, finish), workers
    for cid, a, b in chunks:
        finish(cid, runner.run(np.arange(a, b), points.block(a, b)))
    return "this process", 1


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


def _can_fork() -> bool:
    import multiprocessing as mp
    return "fork" in mp.get_all_start_methods()


_FORKED = None   # (runner, points) of this worker process, set by its pool's initializer


def _forked_init(runner, points):
    global _FORKED
    signal.signal(signal.SIGINT, signal.SIG_IGN)      # the parent stops the pool
    _FORKED = (runner, points)


def _forked_chunk(job):
    cid, a, b = job
    runner, points = _FORKED
    chunk = runner.run(np.arange(a, b), points.block(a, b))
    # Results travel without their Simulator; the parent gives them its own
    chunk.results = [None if r is None else r.detached() for r in chunk.results]
    return cid, chunk


def _run_forked(runner, points, chunks, workers, finish) -> str:
    """Chunks in forked worker processes; each pool hands its workers its own
    job through the initializer (inherited by fork, never pickled), so two
    sweeps at once cannot swap jobs."""
    import multiprocessing as mp
    with mp.get_context("fork").Pool(workers, initializer=_forked_init,
                                      initargs=(runner, points)) as pool:
        for cid, chunk in pool.imap_unordered(_forked_chunk, chunks):
            finish(cid, chunk)
    return f"{workers} processes"


def _rebuild(sim, state):
    if isinstance(state, Result):
        return state
    drive = state.get("_drive")          # a run with inputs reads through them (driven.py)
    return Result.attach(sim if drive is None else Driven(sim, drive), state)


def _windowed(chunks, submit, result, window, finish):
    """Keep at most ``window`` chunks in flight (points are made as chunks are
    submitted, so memory stays bounded), finishing them as they complete."""
    from concurrent.futures import FIRST_COMPLETED, wait
    todo, running = iter(chunks), {}
    for cid, a, b in todo:
        running[submit(cid, a, b)] = cid
        if len(running) >= window:
            break
    while running:
        done, _ = wait(list(running), return_when=FIRST_COMPLETED)
        for f in done:
            finish(running.pop(f), result(f))
            nxt = next(todo, None)
            if nxt is not None:
                running[submit(*nxt)] = nxt[0]


def _run_dask(client, sim, points, fixed, settings, chunks, finish, inputs=None) -> str:
    """One task per chunk, a few per worker in flight; the rig travels once
    to every worker (scattered) and is built there once
    (sweep_runner.run_remote keeps it). Tasks of a lost worker are run again
    by Dask on the others."""
    from distributed import as_completed
    key, data = payload(sim, points.names, fixed, settings, inputs)
    shipped = client.scatter(data, broadcast=True)
    n_workers = max(len(client.scheduler_info().get("workers", {})), 1)
    todo, ids = iter(chunks), {}

    def submit(cid, a, b):
        f = client.submit(run_remote, key, shipped, np.arange(a, b), points.block(a, b),
                          key=f"pdbfs-sweep-{key}-{cid}", pure=False)
        ids[f.key] = cid
        return f

    first = [submit(*c) for _, c in zip(range(4 * n_workers), todo)]
    pending = as_completed(first)
    for fut in pending:
        finish(ids.pop(fut.key), fut.result())
        nxt = next(todo, None)
        if nxt is not None:
            pending.add(submit(*nxt))
    return f"Dask, {len(client.scheduler_info().get('workers', {}))} worker(s)"


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
