"""Simulation and results: a rig's DAE -> SUNDIALS -> a Result.

    one_run.py     simulate(): one run of a rig, the function users call
    simulator.py   Simulator: CVODES/IDAS through casadi.integrator,
                   integrators cached per setting, clear SolverErrors
    compiled.py    backend="c" (the default where it builds): the DAE's
                   generated C + c/pdbfs_batch.c + CVODE or native/c/pdbfs_erk.c
                   (explicit Runge-Kutta 8(5,3)) in one shared library, ctypes;
                   a run's states on the grid made when first read (c/pdbfs_run_*.c)
    block.py       one thread's buffer of the compiled calls' small arguments and answers
    kept.py        a compiled run kept in the library until its states are read
    replay.py      a run again with everything of the run before: its plan,
                   the compiled call and its Result in a few Python frames
    c_summary.py   a compiled run's summary from the run itself (no second run)
    on_grid.py     outputs, rates and event indicators on a whole grid
    result.py      Result: arrays by dotted name, values off the grid, peaks
                   and crossings located on the solution, CSV, pandas, plot
    summary.py     what a test engineer reads off a pulse (peak pressure,
                   duration, restitution, complete or not, each blow)
    summary_run.py the summary's own solution: a fixed grid, until the pulse is over
    impulse.py     impulses and Guo & Batzer's restitution of sampled forces
    contact_impulse.py  a contact force's impulse integrated by the solver
                   (a quadrature on the solution: the summary's restitution)
    stats.py       solver statistics under one set of names
    initialize.py  the start solved before integration: free states, initial
                   equations, initial="steady" (Newton, exact Jacobian)
    newton.py      one damped Newton run on the start system, where it stopped and why
    start_branches.py  the start across one-sided laws: guesses past their kinks
                   where Newton stops at a singular Jacobian; one solution or a refusal
    linearize.py   A, B, C, D at an operating point (algebraic variables
                   eliminated), modes: omega, frequency, damping, shape
    kinks.py       one-sided laws exactly at their kink at that point: the side linearized
    settings.py    tolerances, method, output grid and argument types, checked first
    inputs.py      parameters, start values, grid and settings of a run as vectors,
                   checked; what depends on the rig alone made once
    input_traces.py  the rig's inputs of a run (traces, numbers, functions) checked,
                   piecewise linear: the segments and their entries of p
    input_function.py  an input given as a function of time, sampled into a trace
    driven.py      a run with inputs, segment by segment, and the Simulator its
                   Result reads through (each point with its own inputs)
    driven_trajectory.py  a run with inputs as CasADi expressions of parameters
                   (calibration and design with a measured command)
    memory.py      sizes that cannot fit in the memory available, refused up front
    time_events.py switch times: integrated from switch to switch, never stepped over
    trajectory.py  the simulation as a differentiable CasADi Function of
                   chosen parameters (CVODES sensitivities)
    vectorize.py   CasADi output functions evaluated on whole numpy rows
    plotting.py    matplotlib plots of a Result

May import: pdbfs.errors, pdbfs.modelling (the DAE), pdbfs.native (C code
generation, SUNDIALS). Never the component library, the studies, the FMU
exporter or the rigs in pdbfs.models.
"""
from .result import Result
from .one_run import simulate
from .simulator import MAX_NUM_STEPS, Simulator
from .summary import KEYS as SUMMARY_KEYS
from .summary import UNITS as SUMMARY_UNITS
from .summary import summarize
from .linearize import Linearization, linearize
from .trajectory import trajectory_function

__all__ = ["Result", "Simulator", "simulate", "MAX_NUM_STEPS", "summarize", "SUMMARY_KEYS",
           "SUMMARY_UNITS", "trajectory_function", "linearize", "Linearization"]
