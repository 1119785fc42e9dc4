"""Exact derivatives for an FMU's directional, adjoint and output derivative calls.

CasADi differentiates the state derivatives and the exposed outputs,
``f = [der(x); y_exposed]``, with respect to the states and the parameters,
``q = [x; p]``: ``pdbfs_fwd`` (forward AD) gives ``J v`` for a seed ``v``
over q, ``pdbfs_adj`` (reverse AD) gives ``J^T w`` for a seed ``w`` over f,
each one evaluation whatever the number of knowns or unknowns.

``pdbfs_yder`` gives the first and second time derivatives of the states
and the outputs along the solution, ``D e = de/dt + de/dx der(x)`` and
``D(D e)``: the inputs, ``u + du (t - t_ref)`` in the equations, enter
through ``de/dt`` with their slopes. The C (``c/derivatives.c``) maps
value references onto the seeds and results.
"""
from __future__ import annotations

import casadi as ca

#: the generated functions' names (the C calls them)
NAMES = ("pdbfs_fwd", "pdbfs_adj", "pdbfs_yder")
#: the highest order of the outputs' time derivatives pdbfs_yder gives (maxOutputDerivativeOrder)
OUTPUT_DERIVATIVE_ORDER = 2


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


def output_derivative_function(dae, y_outputs: list[int]) -> ca.Function:
    """``pdbfs_yder(t, x, z, p) = [D q; D(D q)]`` for ``q = [x; y[y_outputs]]``,
    ``D e = de/dt + de/dx der(x)``: the time derivatives of the states and
    the outputs along the solution at (t, x, p)."""
    q = ca.vertcat(dae.x, dae.y[list(y_outputs)]) if y_outputs else dae.x

    def along(e):
        return ca.jtimes(e, dae.t, ca.SX.ones(1, 1)) + ca.jtimes(e, dae.x, dae.ode)
    d1 = along(q)
    return ca.Function(NAMES[2], [dae.t, dae.x, dae.z, dae.p], [ca.densify(ca.vertcat(d1, along(d1)))],
                       ["t", "x", "z", "p"], ["dq"])
