"""Studies on a rig's DAE: what users run to find a rig, not just simulate it.

    sweeps.py        sweep(): many parameter points on one compiled rig
    sweep_result.py  SweepResult: summaries per point, CSV, table, plot
    paper/           the paper's figures reproduced

May import: pdbfs.errors, pdbfs.modelling, pdbfs.simulation, pdbfs.models
and pdbfs.components. Nothing below imports from here.
"""
from .sweeps import points_of, sweep
from .sweep_result import SweepPoint, SweepResult

__all__ = ["sweep", "points_of", "SweepPoint", "SweepResult"]
