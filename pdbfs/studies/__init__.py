"""Studies on a rig's DAE: what users run to find a rig, not just simulate it.

    sweeps/          sweep(): many points of one compiled rig, locally or on Dask,
                     streamed to disk and resumable (sampling, runner, store, result, cluster)
    sensitivity      sensitivity(): Sobol' indices (SALib) from one sweep
    fitting/         calibrate(), design(), design_map(): a rig fitted to curves
                     (traces, free parameters, signal model, features, objectives,
                     least squares, reports)
    paper/           the paper's figures reproduced
    blows            a blow's damage to a breech (pdbfs.fatigue), and the drop height
                     whose blow does a given damage
    campaign/        campaign(): a rig's blows one after another, each from the
                     temperatures the blows before left (the heat carried between blows
                     by its thermal network), with schedules and an operator's rule;
                     resumable (the sweeps' store)
    labfiles         measured traces in NI TDMS and ASAM MDF files (pdbfs[lab]), read
                     as the tables of CSV traces

May import: pdbfs.errors, pdbfs.modelling, pdbfs.simulation, pdbfs.models,
pdbfs.components and pdbfs.fatigue. Nothing below imports from here.
"""
from .blows import HeightSearch, blow_damage, height_for_damage
from .fitting import (Calibration, Design, DesignMap, Trace, calibrate, design, design_map,
                      read_trace)
from .sensitivity import Sensitivity, sensitivity
from .sweeps import Grid, Points, Sample, SweepPoint, SweepResult, points_of, sweep

__all__ = ["sweep", "points_of", "SweepPoint", "SweepResult", "calibrate", "Calibration",
           "design", "Design", "design_map", "DesignMap", "Trace", "read_trace", "Grid", "Sample",
           "Points", "sensitivity", "Sensitivity", "blow_damage", "height_for_damage",
           "HeightSearch"]
