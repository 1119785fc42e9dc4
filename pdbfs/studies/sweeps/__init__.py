"""Sweeps: many parameter points of one compiled rig, evaluated locally
(threads, processes) or on a Dask cluster, streamed to disk and resumable.

    sweep.py     sweep(): the points, the chunks, the executor
    sampling.py  grids, Latin hypercube / Sobol' samples, Monte Carlo
    runner.py    one chunk of points evaluated (C summaries, or Python)
    executors.py where the chunks run: here, threads, forked processes, Dask
    inputs.py    the rig's inputs in a sweep: the same at every point, or a dimension
    store.py     the manifest and chunk files of a sweep on disk
    result.py    SweepResult: the table of points, pandas
    exports.py   its CSV, plot and text table
    cluster.py   a Dask client: a scheduler's address, or a LocalCluster

May import: pdbfs.errors, pdbfs.modelling, pdbfs.simulation.
"""
from .result import SweepPoint, SweepResult
from .sampling import Grid, Points, Sample
from .sweep import points_of, sweep

__all__ = ["sweep", "points_of", "SweepPoint", "SweepResult", "Grid", "Sample", "Points"]
