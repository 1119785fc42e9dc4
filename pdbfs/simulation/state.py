"""What the simulation layer keeps of one compiled rig: one RigState per DAE.

Everything in it is made of the DAE alone, when first needed, and serves
every later run of the rig: its Simulator (integrators by setting), its
compiled library, what a run's settings decide (their checks, the back end,
the output grid), the rig's own start, method="auto"'s choices and the
Jacobian they come from, a failure's explanation's Jacobian, the names every
Result shares, the compiled summary's layout.

When a rig changes (a component added, a connection made), it compiles a new
DAE, and a new DAE starts with a new, empty RigState: the old state goes with
the old DAE, which holds it (``DAE.companions``). A registry here keyed by
the DAE would keep every DAE alive (its Simulator refers to it). Parameters,
start values and settings are arguments of each run and never make the state
stale: what depends on them is kept by them (settings by their values and
types, the own start by the DAE's parameter list, the method choices by
the values their estimate reads).

May import: nothing of pdbfs (every folder of pdbfs.simulation imports it).
"""
from __future__ import annotations


class RigState:
    """The simulation layer's state of one DAE (``state_of(dae)``): each
    field is filled by the module named, and read there."""

    __slots__ = ("simulator", "compiled", "runs", "own_start", "jac_x", "auto_inputs", "auto",
                 "alg_jacobian", "result_names", "summary_layout")

    def __init__(self):
        #: the rig's Simulator, Simulator.of's answer (run/simulator.py)
        self.simulator = None
        #: the compiled library, a CompiledODE, once built or loaded (run/compiled.py)
        self.compiled = None
        #: a run's settings (their values and types) -> what they decide: the back end,
        #: the output grid (read-only) and its address (setup/inputs.py)
        self.runs = {}
        #: (the DAE's parameter list, p, x0) of the rig's own parameters and declared
        #: start, read-only (setup/inputs.py)
        self.own_start = None
        #: d(ode)/dx, a CasADi Function of (t, x, p) (run/stiffness.py)
        self.jac_x = None
        #: (the states, the parameters) d(ode)/dx depends on: what "auto"'s estimate reads
        #: of a run (run/stiffness.py)
        self.auto_inputs = None
        #: method="auto"'s choices by what their estimate read, and by its modes (run/stiffness.py)
        self.auto = {}
        #: d(alg)/dz, a CasADi Function of (t, x, z, p) (run/failures.py)
        self.alg_jacobian = None
        #: the index, units, descriptions and names every Result shares (results/result.py)
        self.result_names = None
        #: the rig's summary keys and their picker from the driver's order (results/c_summary.py)
        self.summary_layout = None


def state_of(dae) -> RigState:
    """The RigState of ``dae``: made on the first request, kept with the DAE."""
    state = dae.companions.get(RigState)
    if state is None:
        state = dae.companions.setdefault(RigState, RigState())
    return state
