"""What a run is set up from, checked before anything is integrated.

    settings.py    tolerances, method, output grid and argument types, checked first
    inputs.py      parameters, start values, grid and settings of a run as vectors,
                   checked; what depends on the rig alone made once (mixed into
                   the Simulator)
    memory.py      sizes that cannot fit in the memory available, refused up front;
                   the probe a compiled run's record of its steps grows within
    limits.py      variables declared valid in a range (min=, max=): a run leaving
                   one stops there with a SolverError naming it and the time
    initialize.py  the start solved before integration: free states, initial
                   equations, initial="steady" (Newton, exact Jacobian)
    newton.py      one damped Newton run on the start system, where it stopped and why
    start_branches.py  the start across one-sided laws: guesses past their kinks
                   where Newton stops at a singular Jacobian; one solution or a refusal
    input_traces.py  the rig's inputs of a run (traces, numbers, functions) checked,
                   piecewise linear: the segments and their entries of p
    input_layout.py  a trace's one layout: (t, u), or named columns; rows refused
    input_function.py  an input given as a function of time, sampled into a trace
    time_events.py where a CasADi run stops and restarts (through the Simulator it
                   is given): from switch to switch, never stepped over, and at
                   every state event, located
    vectorize.py   CasADi functions evaluated on whole numpy rows (the checks'
                   and the outputs')

May import: pdbfs.errors, pdbfs.modelling, pdbfs.native, pdbfs.simulation.state;
no other folder of pdbfs.simulation (every other folder may import this one).
"""
