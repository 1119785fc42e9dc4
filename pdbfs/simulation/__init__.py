"""Simulation and results: a rig's DAE -> SUNDIALS or compiled C -> a Result.

    setup/     what a run is set up from, checked before anything is
               integrated: settings, parameters and start values as vectors,
               the start solved (initial equations, steady state), memory,
               switch times, the rig's inputs of a run as piecewise-linear traces
    run/       one run: simulate(), the Simulator (CVODES/IDAS through CasADi),
               the compiled backend (one shared library per rig, ctypes), a
               run with inputs segment by segment, method="auto", what a
               failure means
    results/   what a run gives: Result, its summary (the compiled run's own,
               or its own solution's), impulses and restitution, peaks and
               crossings on the solution, outputs on a grid, plots
    analysis/  beyond a run: linearization and modes, the simulation as a
               differentiable CasADi Function of parameters
    state      what the layer keeps of one compiled rig (RigState: its
               Simulator, compiled library, what its runs' settings decided),
               held by the DAE and gone with it when the rig changes

Inside, imports go one way: setup <- results <- run <- analysis (each folder
may import those before it, and state; its __init__ says so). The C the compiled
backend's library is built from is pdbfs.native's (native/c/library/ and
native/c/shared/).

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, SUNDIALS). Never the component library, the studies, the FMU
exporter or the rigs in pdbfs.models.
"""
from .results.result import Result
from .run.one_run import simulate
from .run.simulator import MAX_NUM_STEPS, Simulator
from .results.summary import KEYS as SUMMARY_KEYS
from .results.summary import UNITS as SUMMARY_UNITS
from .results.summary import summarize
from .analysis.linearize import Linearization, linearize
from .analysis.trajectory import trajectory_function

__all__ = ["Result", "Simulator", "simulate", "MAX_NUM_STEPS", "summarize", "SUMMARY_KEYS",
           "SUMMARY_UNITS", "trajectory_function", "linearize", "Linearization"]
