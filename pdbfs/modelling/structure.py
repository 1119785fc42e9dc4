"""Structural analysis: from flat equations to one simplified CasADi DAE.

1. parameters bound to other parameters are substituted (calculated ones);
2. aliases are eliminated, derivatives included (aliases.py);
3. the rest is matched (balance: every unknown determined by one equation),
   sorted into blocks (BLT), and each block linear in its unknowns is solved
   symbolically; nonlinear blocks stay algebraic for IDAS (blt.py).

A constraint between states that is not an alias (a high-index DAE) is
differentiated as often as it needs, with dummy derivatives (index.py:
Pantelides' algorithm, any index to index 1, for IDAS); one that stays
singular is refused, naming the states, equations and connections.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError, ParameterError

from .casadi_helpers import subst as _subst
from .dae import DAE, InputInfo, ParamInfo, VarInfo
from .flatten import FlatSystem
from .initialization import attach_initial
from .passes import reduced_start
from .passes.aliases import Aliases
from .passes.blt import solve_blt
from .passes.index import overdetermined, reduce_index
from .passes.smoothness import Jumps
from .rig_inputs import T_REF
from .symbols import quantity


def simplify(flat: FlatSystem, name: str) -> DAE:
    """The DAE of a flat system, named ``name``: aliases eliminated, the index
    reduced, the equations sorted and solved where they can be (BLT)."""
    t = flat.time
    free, calculated, p_old, p_new = _parameters(flat)
    eqs = list(zip(_each(flat.equations, p_old, p_new), [w for _, w in flat.equations]))
    events = list(zip(_each(flat.events, p_old, p_new), [w for _, w in flat.events]))
    # time events first among the events (the C drivers read their times from them)
    switch = list(zip(_each(flat.time_events, p_old, p_new), [w for _, w in flat.time_events]))
    events = [(t - c, w) for c, w in switch] + events
    conditions = list(zip(_each(flat.conditions, p_old, p_new), [w for _, w in flat.conditions]))
    starts = [v for v in flat.vars if isinstance(v.start, ca.SX)]
    for v, e in zip(starts, _each([(v.start, None) for v in starts], p_old, p_new)):
        v.start = e
    # the inputs' values, slopes and t_ref end p (rig_inputs.py); p_val: p's defaults
    ins = flat.inputs
    p_sym = ca.vertcat(*[p.sym for p in free], *[i.value for i in ins], *[i.slope for i in ins],
                       *([T_REF] if ins else []))
    p_val = [p.value for p in free] + ([i.decl.start for i in ins] + [0.0] * (len(ins) + 1)
                                       if ins else [])

    al = Aliases(flat, t)
    al.jumps = Jumps(t, [(c, w, flat.event_text.get(w, "")) for c, w in switch],
                     {v.name: v.start for v in flat.vars if v.start is not None}, p_sym,
                     [p.name for p in free])
    eqs = al.eliminate(eqs)

    states = [v for v in flat.vars if v.name not in al.gone
              and (v.is_state or (v.der is not None and v.der.name() in al.used_der))]
    state_ids = {id(v) for v in states}
    algebraic = [v for v in flat.vars if v.name not in al.gone and id(v) not in state_ids]
    unknowns, labels = [], []
    for v in states:
        if v.der is None:
            raise ModelError(f"{v.name} is declared a state but no equation uses der({v.name})")
        if v.der.name() not in al.gone:
            unknowns.append(v.der)
            labels.append(f"der({v.name})")
    for v in algebraic:
        unknowns.append(v.sym)
        labels.append(v.name)

    dropped, constraints = [], []        # states made algebraic by index reduction, and why
    pivots = []                          # what linear blocks solved symbolically divide by
    try:
        solved, z_syms, z_labels, alg = solve_blt(eqs, unknowns, labels, pivots)
    except ModelError as singular:
        start = ({v.name: v.start for v in flat.vars if v.start is not None}, p_sym, p_val)
        reduced = reduce_index(eqs, unknowns, labels, states, algebraic, al, t, start)
        try:
            if reduced is None:
                raise singular
            pivots.clear()
            solved, z_syms, z_labels, alg = solve_blt(*reduced[:3], pivots=pivots)
        except ModelError:
            _explain_state_constraint(flat, eqs, unknowns, states)
            raise singular from None
        dropped = [v for v in states if all(v is not w for w in reduced[3])]
        eqs, unknowns, labels, states, constraints = reduced

    # everything in terms of (t, x, z, p)
    s_keys = ca.vertcat(*[s for s, _ in solved]) if solved else ca.SX(0, 1)
    s_vals = ca.vertcat(*[e for _, e in solved]) if solved else ca.SX(0, 1)

    def final(expr):
        expr = al.resolve(expr)
        return _subst(expr, s_keys, s_vals)

    # ode, outputs and events in terms of (t, x, z, p), in one substitution
    x = ca.vertcat(*[v.sym for v in states])
    y_vars = flat.vars
    parts = [[v.der for v in states], [v.sym for v in y_vars], [e for e, _ in events]]
    done = final(ca.vertcat(*[e for part in parts for e in part]))
    n_x, n_y = len(states), len(y_vars)
    ode = done[:n_x] if states else ca.SX(0, 1)
    y = done[n_x:n_x + n_y]
    ev = done[n_x + n_y:] if events else ca.SX(0, 1)
    x0 = ca.vertcat(*[_start(v) for v in states]) if states else ca.SX(0, 1)
    _check_consistent_start(flat, al, states, x0, p_sym, p_val, final, t)

    z = ca.vertcat(*z_syms) if z_syms else ca.SX(0, 1)
    by_name = {v.name: v for v in flat.vars}
    z0 = ca.vertcat(*[_start(by_name[n]) if n in by_name else ca.SX(0.0) for n in z_labels]) \
        if z_syms else ca.SX(0, 1)
    alg_expr = final(ca.vertcat(*alg)) if alg else ca.SX(0, 1)

    info = lambda v: VarInfo(v.name, v.unit, v.description, v.output, *v.limits, span=v.span)
    dae = DAE(name=name, t=t, x=x, z=z, p=p_sym, ode=ode, alg=alg_expr, x0=x0, y=y,
               events=ev, x_info=[info(v) for v in states],
               z_info=[VarInfo(n, by_name[n].unit if n in by_name else "",
                               "algebraic unknown of a nonlinear block") for n in z_labels],
               params=[_param_info(p) for p in free], y_info=[info(v) for v in y_vars],
               event_names=[w for _, w in events], calculated=calculated, z0=z0,
               time_events=ca.vertcat(*[c for c, _ in switch]) if switch else ca.SX(0, 1),
               conditions=conditions + al.jumps.conditions + _loops(pivots, free),
               event_text=dict(flat.event_text),
               inputs=[InputInfo(i.name, i.decl.unit, i.decl.description, i.decl.start)
                       for i in ins])
    reduced_start.record(dae, dropped, constraints)
    reduced_start.check(dae, dae.p_default())
    attach_initial(dae, flat, states, al, lambda e: final(_subst(e, p_old, p_new)))
    return dae


def _loops(pivots, free) -> list:
    """Conditions that the linear blocks solved symbolically (an algebraic
    loop of blocks, y = 1 + k y) are solvable: a pivot of parameters only
    that can be 0 (not a product or sum of positive ones, as a mass) must
    not be (it is divided by: NaN where it is). A pivot that is 0 whatever
    the parameters is refused now."""
    names = {p.name for p in free}
    positive = {p.name for p in free if p.decl.positive}
    out = []
    for pivot, where in pivots:
        what = "; ".join(dict.fromkeys(where))
        if pivot.is_zero() or (pivot.is_constant() and float(pivot) == 0.0):
            raise ModelError(f"the equations {what} (an algebraic loop) have no unique solution: "
                             "break the loop (a FirstOrder block in it)")
        inside = {s.name() for s in ca.symvar(pivot)}
        if not inside or not inside <= names:
            continue                     # of states too: not known before the run
        if not _can_vanish(pivot, positive):
            continue                     # a mass, an area's inverse: never 0
        out.append((ca.fabs(pivot) - 1e-300, (
            what, "the algebraic loop through it has no unique solution at these values (its "
            "equations are singular, as y = 1 + y is); change the loop's gains or break it (a "
            "FirstOrder block in it)", sorted(inside))))
    return out


def _can_vanish(e, positive) -> bool:
    """Whether the expression ``e`` (of parameters) may be 0: a sum or a
    difference may cancel, a parameter not declared positive may be 0; a
    product only through a factor, a quotient through its numerator."""
    if e.is_constant():
        return float(e) == 0.0
    if e.is_symbolic():
        return e.name() not in positive
    op = e.op()
    if op == ca.OP_MUL:
        return any(_can_vanish(e.dep(k), positive) for k in range(2))
    if op in (ca.OP_DIV,):
        return _can_vanish(e.dep(0), positive)
    if op in (ca.OP_NEG, ca.OP_SQ, ca.OP_SQRT, ca.OP_FABS):
        return _can_vanish(e.dep(0), positive)
    if op in (ca.OP_EXP, ca.OP_INV):     # never 0
        return False
    return True


def _each(items, keys, vals) -> list:
    """The expressions of (expr, where) items with keys -> vals, in one substitution."""
    if not items:
        return []
    out = _subst(ca.vertcat(*[e for e, _ in items]), keys, vals)
    return ca.vertsplit(out, 1)


# -- parameters ------------------------------------------------------------------
def _param_info(p) -> ParamInfo:
    d = p.decl
    return ParamInfo(p.name, float(p.value), d.unit, d.description, d.min, d.max,
                     d.positive, d.tunable)


def _parameters(flat):
    """Split free parameters from bound ones; express bound ones in free ones."""
    free = [p for p in flat.params if not isinstance(p.value, ca.SX)]
    bound = [p for p in flat.params if isinstance(p.value, ca.SX)]
    for p in free:
        p.decl.check(p.value, p.name)
    b_sym = ca.vertcat(*[p.sym for p in bound]) if bound else ca.SX(0, 1)
    exprs = ca.vertcat(*[p.value for p in bound]) if bound else ca.SX(0, 1)
    for _ in range(len(bound) + 1):
        if not bound or not ca.depends_on(exprs, b_sym):
            break
        exprs = _subst(exprs, b_sym, exprs)
    else:
        raise ParameterError("parameter bindings form a cycle: "
                             + ", ".join(p.name for p in bound))
    calculated = {}
    for k, p in enumerate(bound):
        e = exprs[k]
        if not (e.is_symbolic()):   # plain aliases of another parameter are not listed
            calculated[p.name] = (e, VarInfo(p.name, p.decl.unit, p.decl.description))
    return free, calculated, b_sym, exprs


def _start(v):
    if v.start is None:
        return ca.SX(0.0)
    return ca.SX(v.start)


# -- alias elimination ---------------------------------------------------------------
def _check_consistent_start(flat, al, states, x0, p_sym, p_val, final, t):
    """A state eliminated as an alias must start where its replacement starts
    (checked at the default parameter values)."""
    gone = [(v, where) for v, _, where in al.states_gone if v.is_state or v.start is not None]
    if not gone:
        return
    x = ca.vertcat(*[v.sym for v in states]) if states else ca.SX(0, 1)
    mine = ca.vertcat(*[_start(v) for v, _ in gone])
    theirs = _subst(final(ca.vertcat(*[v.sym for v, _ in gone])), x, x0)
    f = ca.Function("start_check", [t, p_sym], [mine, theirs])
    a, b = (np.array(r).ravel() for r in f(0.0, p_val))
    for (v, where), s_mine, s_theirs in zip(gone, a, b):
        if abs(s_mine - s_theirs) > 1e-9 * (1.0 + abs(s_mine)):
            raise ModelError(
                f"{v.name} starts at {quantity(s_mine, v.unit)}, but {where} ties it to a value "
                f"that starts at {quantity(s_theirs, v.unit)}; give rigidly connected bodies "
                "consistent start values")


# -- constraints among states ----------------------------------------------------------
def _explain_state_constraint(flat, eqs, unknowns, states):
    """A structurally singular system whose over-determined part (the
    equations reached from an unmatched one by alternating paths, as in
    Dulmage-Mendelsohn) relates states of several components is a
    constraint between states that alias elimination could not remove:
    name the states, the equations and the connections that join their
    components, and say what to do. Runs only when the analysis failed."""
    if not eqs or not unknowns:
        return
    block = overdetermined(eqs, unknowns)
    state_names = {v.name for v in states}
    tied = sorted({x.name() for i in block for x in ca.symvar(eqs[i][0])} & state_names)
    owners = {n.rsplit(".", 1)[0] for n in tied}
    if len(owners) < 2:
        return
    joins = [w for _, w in flat.equations
             if w.startswith("connect(") and sum(f"{o}." in w for o in owners) >= 2]
    via = f", joined by {'; '.join(dict.fromkeys(joins))}" if joins else ""
    raise ModelError(
        f"a constraint between states: {', '.join(tied)} are tied to each other with nothing "
        f"left to determine (in {'; '.join(eqs[i][1] for i in sorted(block))}{via}): a loop with "
        "no compliance or resistance in it, which neither alias elimination nor index "
        "reduction (Pantelides' algorithm, dummy derivatives) makes regular: put a "
        "compliance or resistance between them (a Spring, Damper, Orifice or LaminarLeak)")
