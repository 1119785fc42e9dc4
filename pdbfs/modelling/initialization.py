"""What the start of a rig is made of, in the DAE's terms: which states
start where their ``start`` says (``fixed``, the default) and which are
free (``State(..., fixed=False)`` or ``Component.free``), and the initial
equations the components declare (``initial_equations()``), expressed in
(t, x, z, p) like every other equation: derivatives become the right-hand
side of the ODE, aliases their replacements.

The solution (Newton with the exact Jacobian) is the simulation's business:
pdbfs.simulation.initialize.
"""
from __future__ import annotations

import casadi as ca

from pdbfs.errors import ModelError


def attach_initial(dae, flat, states, al, final):
    """Set ``dae.x_fixed``, ``dae.init`` and ``dae.init_names`` from the flat
    system. ``final`` maps an expression of the flat symbols (parameters
    substituted) to one of (t, x, z, p)."""
    free = {v.name for v in states if not v.fixed}
    # a free state eliminated as an alias frees the state that replaces it
    x_names = {v.name for v in states}
    for v, _, _ in al.states_gone:
        if not v.fixed:
            free |= {s.name() for s in ca.symvar(al.resolve(v.sym))} & x_names
    dae.x_fixed = [v.name not in free for v in states]
    if not flat.initial:
        dae.init, dae.init_names = ca.SX(0, 1), []
        return
    exprs = final(ca.vertcat(*[e for e, _ in flat.initial]))
    known = {s.name() for s in ca.symvar(ca.vertcat(dae.t, dae.x, dae.z, dae.p))}
    for k, (_, where) in enumerate(flat.initial):
        strangers = sorted({s.name() for s in ca.symvar(exprs[k])} - known)
        if strangers:
            raise ModelError(f"{where}: uses {', '.join(strangers)}, which the rig's simplified "
                             "equations do not keep (a derivative of a variable that is not a "
                             "state?)")
    dae.init = exprs
    dae.init_names = [w for _, w in flat.initial]
