"""What the start of a rig is made of, in the DAE's terms: which states
start where their ``start`` says (``fixed``, the default) and which are
free (``State(..., fixed=False)`` or ``Component.free``), and the initial
equations the components declare (``initial_equations()``), expressed in
(t, x, z, p) like every other equation: derivatives become the right-hand
side of the ODE, aliases their replacements.

``start_system`` and ``start_residual`` state the start as equations in
the unknowns w = [free states; z]; solving them is the simulation's
business (pdbfs.simulation.setup.initialize) and the FMU's (pdbfs.native.initial).
"""
from __future__ import annotations

import re

import casadi as ca

from pdbfs.errors import ModelError, ParameterError


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


def check_initial(initial, dae):
    """``initial`` is None, "steady" or a list of state names."""
    if initial is None or initial == "steady":
        return
    if isinstance(initial, str) or not all(isinstance(n, str) for n in initial):
        raise ParameterError(f"initial={initial!r}: give 'steady' or a list of state names")
    bad = [n for n in initial if n not in dae.x_names]
    if bad:
        raise ParameterError(f"initial: {', '.join(bad)} not a state of rig {dae.name}; "
                             f"states: {', '.join(dae.x_names)}")


def needs_solving(dae, initial=None) -> bool:
    """Whether the start must be solved (free states, initial equations or ``initial``)."""
    fixed = dae.x_fixed or [True] * dae.x.numel()
    return initial is not None or not all(fixed) or (dae.init is not None and dae.init.numel() > 0)


def start_system(dae, initial=None):
    """(indices of the free states, equations in (t, x, z, p), their names)
    of the start: the declared initial equations, or with ``initial="steady"``
    der(x) = 0 for every state (which replaces them), or with a list of
    states der(x) = 0 for those besides them."""
    check_initial(initial, dae)
    nx = dae.x.numel()
    fixed = list(dae.x_fixed or [True] * nx)
    init = dae.init if dae.init is not None else ca.SX(0, 1)
    names = list(dae.init_names)
    if initial == "steady":
        steady = list(range(nx))
        init, names = ca.SX(0, 1), []
    else:
        steady = [dae.x_names.index(n) for n in (initial or [])]
    free = sorted(set(steady) | {i for i in range(nx) if not fixed[i]})
    eqs = [init[k] for k in range(init.numel())] + [dae.ode[i] for i in steady]
    names += [f"der({dae.x_names[i]}) = 0" for i in steady]
    return free, eqs, names


def square_start(dae, free, eqs, eq_names):
    """(unknowns, equation names) of the start system, or a ModelError naming
    both when there are not as many equations as unknowns."""
    nz = dae.z.numel()
    unknowns = [dae.x_names[i] for i in free] + dae.z_names
    eq_names = eq_names + [f"algebraic equation {k + 1}" for k in range(nz)]
    if len(eqs) + nz != len(unknowns):
        raise ModelError(
            f"the start of rig {dae.name} has {len(eqs) + nz} equations "
            f"({', '.join(eq_names) or 'none'}) for {len(unknowns)} unknowns "
            f"({', '.join(unknowns) or 'none'}): give as many initial equations as free states")
    return unknowns, eq_names


def start_residual(dae, free, eqs):
    """(w, xg, G): the unknowns w = [free states; z], a symbol xg for the
    values of every state (the fixed ones are taken from it) and the
    residuals G(w, t, xg, p) = [eqs; algebraic equations]."""
    G = ca.vertcat(*eqs, dae.alg) if (eqs or dae.z.numel()) else ca.SX(0, 1)
    return on_unknowns(dae, free, G)


def on_unknowns(dae, free, expr):
    """(w, xg, expr'): an expression of (t, x, z, p) written in the unknowns
    w = [free states; z] of the start and the symbol xg of every state's
    value (the fixed states are taken from it), as ``start_residual`` does
    for the residuals (and the start search for the event indicators)."""
    wx = ca.SX.sym("wx", len(free))
    w = ca.vertcat(wx, dae.z)
    xg = ca.SX.sym("xg", dae.x.numel())
    xs = ca.vertsplit(xg, 1) if dae.x.numel() else []
    for k, i in enumerate(free):
        xs[i] = wx[k]
    if xs:
        expr = ca.substitute(expr, dae.x, ca.vertcat(*xs))
    return w, xg, expr


_RATE = re.compile(r"der\((.+)\) = 0")


def rate_dependencies(dae, i) -> list:
    """The states the rate der(x_i) depends on (structurally; through the
    algebraic variables, on every state the algebraic equations use)."""
    rate = dae.ode[i]
    via_z = dae.z.numel() > 0 and ca.depends_on(rate, dae.z)
    return [n for j, n in enumerate(dae.x_names)
            if ca.depends_on(rate, dae.x[j]) or (via_z and ca.depends_on(dae.alg, dae.x[j]))]


def rate_hint(dae, eq_names, unknowns) -> str:
    """What would fix the start's ``unknowns`` that equations ``der(x) = 0``
    (a state started at rest) among ``eq_names`` leave free: the states each
    rate depends on that start where declared, to start at rest too ('' when
    there are none: no other choice of states would help, the rig itself
    leaves them free)."""
    free = set(unknowns)
    add = []
    for name in eq_names:
        m = _RATE.fullmatch(name)
        if m is None or m.group(1) not in dae.x_names:
            continue
        x = m.group(1)
        deps = rate_dependencies(dae, dae.x_names.index(x))
        fixed = [n for n in deps if n not in free]
        if not fixed:
            continue            # it depends on unknowns only: no other choice would help
        body = x.rsplit(".", 1)[0]
        add += [n for n in fixed if n.rsplit(".", 1)[0] == body] or fixed
    if not add:
        return ""
    add = list(dict.fromkeys(add))
    return f"; start {', '.join(add)} at rest too"


def start_pattern(dae):
    """An expression of p with the dependency pattern of the solved start
    (for the FMU's InitialUnknowns): a free state depends on every
    parameter the start system uses (the fixed states' starts included)."""
    if not needs_solving(dae):
        return dae.x0
    free, eqs, _ = start_system(dae)
    _, xg, G = start_residual(dae, free, eqs)
    G = ca.vertcat(ca.substitute(G, xg, dae.x0), *[dae.x0[i] for i in free])
    used = [dae.p[j] for j in range(dae.p.numel()) if ca.depends_on(G, dae.p[j])]
    link = sum(used, ca.SX(0.0))        # a structural term in each used parameter
    return ca.vertcat(*[dae.x0[i] + link if i in free else dae.x0[i]
                        for i in range(dae.x.numel())])
