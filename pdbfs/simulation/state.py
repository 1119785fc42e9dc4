"""What the simulation layer keeps of one compiled rig: one RigState per DAE.

Everything in it is made of the DAE alone, when first needed, and serves
every later run of the rig: its Simulator (integrators by setting, run
plans), its compiled library, the plans of ``rig.simulate()`` with no
options, the Jacobians that method="auto" and a failure's explanation use,
the names every Result shares, the compiled summary's layout.

When a rig changes (a component added, a connection made), it compiles a new
DAE, and a new DAE starts with a new, empty RigState: the old state goes with
the old DAE, which holds it (``DAE.companions``). A registry here keyed by
the DAE would keep every DAE alive (its Simulator refers to it). Parameters,
start values and settings are arguments of each run and never make the state
stale: what depends on them is kept by them (the Simulator's cache).

May import: nothing of pdbfs (every folder of pdbfs.simulation imports it).
"""
from __future__ import annotations


class RigState:
    """The simulation layer's state of one DAE (``state_of(dae)``): each
    field is filled by the module named, and read there."""

    __slots__ = ("simulator", "compiled", "own_plans", "jac_x", "alg_jacobian", "result_names",
                 "summary_layout")

    def __init__(self):
        #: the rig's Simulator, Simulator.of's answer (run/simulator.py)
        self.simulator = None
        #: the compiled library, a CompiledODE, once built or loaded (run/compiled.py)
        self.compiled = None
        #: t_end -> (Simulator, Plan) of rig.simulate(t_end) with no options (run/replay.py)
        self.own_plans = {}
        #: d(ode)/dx, a CasADi Function of (t, x, p) (run/stiffness.py)
        self.jac_x = None
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
