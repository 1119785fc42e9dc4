"""One run of a rig: the Simulator, its two back ends and the method choice.

    one_run.py     simulate(): one run of a rig, the function users call
    simulator.py   Simulator: CVODES/IDAS through casadi.integrator,
                   integrators cached per setting, clear SolverErrors
    compiled.py    backend="c" (the default where it builds): the DAE's
                   generated C + the library's drivers (native/c/library/) +
                   CVODE or the explicit Runge-Kutta 8(5,3) (native/c/shared/) in
                   one shared library, ctypes; a run's states on the grid made
                   when first read
    compiled_build.py  the compiled library built (zig cc) and cached on disk: the drivers
                   once per machine, a rig's own C linked with them
    backends.py    "auto" and a CVODE method without CVODE at hand: CasADi, with a warning
    driven.py      a run with the rig's inputs, segment by segment (the compiled
                   driver's in one call: native/c/library/pdbfs_segments.c), and the
                   Simulator its Result reads through (each point with its own inputs)
    block.py       one thread's buffer of the compiled calls' small arguments and answers
    kept.py        a compiled run kept in the library until its states are read
    failures.py    what a failed integration most likely means (SolverError texts)
    stats.py       solver statistics under one set of names
    stiffness.py   method="auto": the method that suits the rig's modes, chosen
                   once per class of runs

May import: pdbfs.errors, pdbfs.files, pdbfs.modelling, pdbfs.native,
pdbfs.simulation.state, pdbfs.simulation.setup and pdbfs.simulation.results;
never analysis.
"""
