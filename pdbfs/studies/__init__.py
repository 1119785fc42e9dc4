"""Studies on a rig's DAE: what users run to find a rig, not just simulate it.

    sweeps.py        sweep(): many parameter points on one compiled rig, locally
                     (threads, processes) or on Dask; streamed to disk, resumable
      sampling.py      grids, Latin hypercube / Sobol' samples, Monte Carlo
      sweep_runner.py  one chunk of points evaluated (C summaries, or Python)
      sweep_store.py   manifest and chunk files of a sweep on disk
      sweep_result.py  SweepResult: the table of points, CSV, pandas, plot
      cluster.py       a Dask client: a scheduler's address, or a LocalCluster
    sensitivity.py   sensitivity(): Sobol' indices (SALib) from one sweep
    calibration.py   calibrate(): a rig's unknown parameters fitted to a trace
    design.py        design(): the settings that give a target pulse
    design_map.py    design_map(): pulse features over two settings, one sweep
      traces.py        measured traces and target curves, read and checked
      unknowns.py      free parameters: scaling, bounds, drop height for speed
      signal_model.py  a rig's output with exact sensitivities on a fine grid
      features.py      peak, time of peak, duration and their gradients
      problems.py      the least-squares problems (curve, features)
      fitting.py       bounded multistart least squares and its statistics
      reports.py       text, plots and CSV of the results
    paper/           the paper's figures reproduced

May import: pdbfs.errors, pdbfs.modelling, pdbfs.simulation, pdbfs.models
and pdbfs.components. Nothing below imports from here.
"""
from .calibration import Calibration, calibrate
from .design import Design, design
from .design_map import DesignMap, design_map
from .sweep_result import SweepPoint, SweepResult
from .sampling import Grid, Points, Sample
from .sensitivity import Sensitivity, sensitivity
from .sweeps import points_of, sweep
from .traces import Trace, read_trace

__all__ = ["sweep", "points_of", "SweepPoint", "SweepResult", "calibrate", "Calibration",
           "design", "Design", "design_map", "DesignMap", "Trace", "read_trace", "Grid", "Sample",
           "Points", "sensitivity", "Sensitivity"]
