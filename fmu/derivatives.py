"""Exact derivatives for an FMU's directional and adjoint derivative calls.

CasADi differentiates the state derivatives and the exposed outputs,
``f = [der(x); y_exposed]``, with respect to the states and the parameters,
``q = [x; p]``: ``pdbfs_fwd`` (forward AD) gives ``J v`` for a seed ``v``
over q, ``pdbfs_adj`` (reverse AD) gives ``J^T w`` for a seed ``w`` over f,
each one evaluation whatever the number of knowns or unknowns. The C
(``c/derivatives.c``) maps value references onto the seeds and results.
"""
from __future__ import annotations

import casadi as ca

#: the generated functions' names (the C calls them)
NAMES = ("pdbfs_fwd", "pdbfs_adj")


def derivative_functions(dae, y_exposed: list[int]) -> list[ca.Function]:
    """``pdbfs_fwd(t, x, z, p, v) = J v`` and ``pdbfs_adj(t, x, z, p, w) = J^T w``
    with ``J = d[ode; y[y_exposed]] / d[x; p]``."""
    f = ca.vertcat(dae.ode, dae.y[list(y_exposed)]) if y_exposed else dae.ode
    q = ca.vertcat(dae.x, dae.p)
    v = ca.SX.sym("v", q.numel())
    w = ca.SX.sym("w", f.numel())
    args, names = [dae.t, dae.x, dae.z, dae.p], ["t", "x", "z", "p"]
    return [ca.Function(NAMES[0], [*args, v], [ca.densify(ca.jtimes(f, q, v))], [*names, "v"], ["jv"]),
            ca.Function(NAMES[1], [*args, w], [ca.densify(ca.jtimes(f, q, w, True))], [*names, "w"], ["jtw"])]
