"""Fitting a rig to curves: calibration to a measured trace, design of the
settings for a target pulse, and the map of pulse features over two settings.

    calibration.py      calibrate(): a rig's unknown parameters fitted to a trace
    design.py           design(): the settings that give a target pulse
    design_map.py       design_map(): pulse features over two settings, one sweep
    traces.py           measured traces and target curves, read (units, columns) and checked
    free_parameters.py  the parameters set free: scaling, bounds, drop height for speed
    arguments.py        the entry points' arguments checked for type, each named when wrong
    signal_model.py     a rig's output with exact sensitivities on the trace's grid
    features.py         peak, time of peak, duration and their gradients
    objectives.py       the least-squares objectives (a curve, or features)
    least_squares.py    bounded multistart least squares and its statistics
    reports.py          text, plots and CSV of the results

May import: pdbfs.errors, pdbfs.modelling, pdbfs.simulation, pdbfs.studies.sweeps,
pdbfs.models and pdbfs.components.
"""
from .calibration import Calibration, calibrate
from .design import Design, design
from .design_map import DesignMap, design_map
from .traces import Trace, read_trace

__all__ = ["calibrate", "Calibration", "design", "Design", "design_map", "DesignMap", "Trace",
           "read_trace"]
