"""Where a sweep's chunks run: in this process, in threads (the compiled
backend's summaries: ctypes releases the GIL), in forked processes (the
CasADi backend) or on a Dask cluster (one task per chunk, the rig built once
per worker). Each finishes the chunks through the sweep's ``finish``."""
from __future__ import annotations

import signal
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .runner import payload, run_remote


def execute(client, sim, points, fixed, settings, chunks, finish, runner, workers):
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
