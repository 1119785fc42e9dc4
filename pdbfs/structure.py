"""Structural analysis: from flat equations to one simplified CasADi DAE.

1. parameters bound to other parameters are substituted (calculated ones);
2. balance is checked per component and, by maximum matching, in total;
3. aliases ``a*u + b*w + c(p, t) = 0`` (a a number, b a number or a
   parameter expression) are eliminated, derivatives included:
   eliminating ``u`` also replaces ``der(u)`` by the derivative of its
   replacement, so a state tied to another state stops being a state (two
   rigidly connected masses become one);
4. the rest is matched, sorted into blocks (BLT), and each block linear in
   its unknowns is solved symbolically; nonlinear blocks stay algebraic.
"""
from __future__ import annotations

import graphlib

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

from .dae import DAE, ParamInfo, VarInfo
from .errors import ModelError, ParameterError
from .flatten import FlatSystem


def simplify(flat: FlatSystem, name: str) -> DAE:
    t = flat.time
    free, calculated, p_old, p_new = _parameters(flat)
    eqs = [(_subst(r, p_old, p_new), w) for r, w in flat.equations]
    events = [(_subst(e, p_old, p_new), w) for e, w in flat.events]
    for v in flat.vars:
        if isinstance(v.start, ca.SX):
            v.start = _subst(v.start, p_old, p_new)
    p_sym = ca.vertcat(*[p.sym for p in free])

    al = _Aliases(flat, t)
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

    solved, z_syms, z_labels, alg = _solve_blt(eqs, unknowns, labels)

    # everything in terms of (t, x, z, p)
    s_keys = ca.vertcat(*[s for s, _ in solved]) if solved else ca.SX(0, 1)
    s_vals = ca.vertcat(*[e for _, e in solved]) if solved else ca.SX(0, 1)

    def final(expr):
        expr = al.resolve(expr)
        return _subst(expr, s_keys, s_vals)

    x = ca.vertcat(*[v.sym for v in states])
    ode = ca.vertcat(*[final(v.der) for v in states]) if states else ca.SX(0, 1)
    y_vars = flat.vars
    y = ca.vertcat(*[final(v.sym) for v in y_vars])
    ev = ca.vertcat(*[final(e) for e, _ in events]) if events else ca.SX(0, 1)
    x0 = ca.vertcat(*[_start(v) for v in states]) if states else ca.SX(0, 1)
    _check_consistent_start(flat, al, states, x0, p_sym, free, final, t)

    z = ca.vertcat(*z_syms) if z_syms else ca.SX(0, 1)
    by_name = {v.name: v for v in flat.vars}
    z0 = ca.vertcat(*[_start(by_name[n]) if n in by_name else ca.SX(0.0) for n in z_labels]) \
        if z_syms else ca.SX(0, 1)
    alg_expr = ca.vertcat(*[final(r) for r in alg]) if alg else ca.SX(0, 1)

    info = lambda v: VarInfo(v.name, v.unit, v.description, v.output)
    return DAE(name=name, t=t, x=x, z=z, p=p_sym, ode=ode, alg=alg_expr, x0=x0, y=y,
               events=ev, x_info=[info(v) for v in states],
               z_info=[VarInfo(n, by_name[n].unit if n in by_name else "",
                               "algebraic unknown of a nonlinear block") for n in z_labels],
               params=[_param_info(p) for p in free], y_info=[info(v) for v in y_vars],
               event_names=[w for _, w in events], calculated=calculated, z0=z0)


def _subst(expr, keys, vals):
    """ca.substitute that tolerates structural zeros and empty key lists."""
    if keys.numel() == 0:
        return expr
    return ca.substitute(ca.SX(expr), keys, ca.densify(ca.SX(vals)))


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
class _Aliases:
    def __init__(self, flat, t):
        self.t = t
        self.by_name = {v.name: v for v in flat.vars}
        self.order = {v.name: i for i, v in enumerate(flat.vars)}
        self.der_owner = {}                  # "der(x)" -> FlatVar x
        for v in flat.vars:
            if v.der is not None:
                self.der_owner[v.der.name()] = v
        self.K = ca.SX(0, 1)                 # eliminated symbols ...
        self.V = ca.SX(0, 1)                 # ... and what replaces them (column vectors)
        self.gone: set[str] = set()
        self.used_der: set[str] = set()
        self.states_gone: list[tuple] = []   # (state FlatVar, replacement)

    def kind(self, s):
        """(rank, order) of a variable-like symbol, or None for p and t."""
        n = s.name()
        if n in self.by_name:
            v = self.by_name[n]
            if v.is_state:
                rank = 4
            elif v.der is not None and v.der.name() in self.used_der:
                rank = 3
            else:
                rank = v.rank - 1      # component variable 1, connector variable 0
            return (rank, -self.order[n])
        if n in self.der_owner:
            return (2, -self.order[self.der_owner[n].name])
        return None

    def unknowns_in(self, r):
        return [s for s in ca.symvar(r) if self.kind(s) is not None]

    def _der_of_expr(self, expr):
        """d/dt of an expression linear in variables, through their der symbols."""
        out = ca.jacobian(expr, self.t)
        for s in self.unknowns_in(expr):
            coeff = ca.jacobian(expr, s)
            n = s.name()
            v = self.by_name.get(n)
            if v is None:
                raise ModelError(f"the rig needs the second derivative of {self.der_owner[n].name}: "
                                 "index reduction of that order is not supported")
            if v.der is None:
                v.der = ca.SX.sym(f"der({v.name})")
                self.der_owner[v.der.name()] = v
            self.used_der.add(v.der.name())
            out = out + coeff * v.der
        return self.resolve(out)   # der(w) may itself be eliminated already

    def eliminate(self, eqs):
        for v in self.by_name.values():
            if v.der is not None:
                self.used_der.add(v.der.name())
        # equations as one column (cheap to substitute into) and their origins
        R = ca.vertcat(*[r for r, _ in eqs]) if eqs else ca.SX(0, 1)
        W = [w for _, w in eqs]
        changed = True
        while changed:           # repeat: an elimination can make new aliases
            changed = False
            i = 0
            while i < R.numel():
                found = self._alias(R[i])
                if found is None:
                    i += 1
                    continue
                u, expr = found
                keys, vals = [u], [expr]
                owner = self.by_name.get(u.name())
                extra, extra_w = [], []
                if owner is not None and owner.der is not None:
                    d_expr = self._der_of_expr(expr)
                    if owner.der.name() not in self.gone:
                        keys.append(owner.der)
                        vals.append(d_expr)
                    else:   # der(u) was already replaced: keep the differentiated equation
                        extra.append(self.resolve(owner.der) - d_expr)
                        extra_w.append(f"derivative of {W[i]}")
                if owner is not None and (owner.is_state or
                                          (owner.der is not None and owner.der.name() in self.used_der)):
                    self.states_gone.append((owner, expr, W[i]))
                R = ca.vertcat(R[:i], R[i + 1:], *extra)
                W = W[:i] + W[i + 1:] + extra_w
                R = self._apply(R, keys, vals)
                changed = True
        kept = []
        for k, where in enumerate(W):
            r = R[k]
            if not self.unknowns_in(r):
                if _identically_zero(r):
                    continue
                raise ModelError(f"over-determined: {where} leaves nothing to determine "
                                 f"(0 = {r}); a redundant connection or a constraint on fixed values?")
            kept.append((r, where))
        return kept

    def _alias(self, r):
        """(u, replacement) if r = a*u + b*w + c with a a non-zero number, b a
        number or an expression of parameters, c free of variables; else None."""
        us = self.unknowns_in(r)
        if not 1 <= len(us) <= 2:
            return None
        uv = ca.vertcat(*us)
        J = ca.jacobian(r, uv)
        if ca.depends_on(J, uv) or ca.depends_on(J, self.t) or \
                any(self.kind(s) is not None for s in ca.symvar(J)):
            return None                          # not linear with constant coefficients
        c0 = ca.substitute(r, uv, ca.DM.zeros(len(us)))
        numeric = [J[k].is_constant() and float(J[k]) != 0.0 for k in range(len(us))]
        if len(us) == 1:
            return (us[0], -c0 / float(J[0])) if numeric[0] else None
        order = sorted(range(2), key=lambda k: self.kind(us[k]))   # lower-ranked first
        for k in order:            # eliminate the lower-ranked one whose coefficient is a number
            if numeric[k]:
                u, w, a, b = us[k], us[1 - k], float(J[k]), J[1 - k]
                if b.is_constant() and float(b) == 0.0:
                    return None
                return u, -(b * w + c0) / a
        return None

    def _apply(self, R, keys, vals):
        """Record the substitution and apply it to R and to earlier ones."""
        for k in keys:
            self.gone.add(k.name())
        kv, vv = ca.vertcat(*keys), ca.densify(ca.vertcat(*vals))
        self.V = ca.vertcat(_subst(self.V, kv, vv), vv)
        self.K = ca.vertcat(self.K, kv)
        return _subst(R, kv, vv)

    def resolve(self, expr):
        return _subst(expr, self.K, self.V)


def _identically_zero(r) -> bool:
    if r.is_zero():
        return True
    f = ca.Function("f", ca.symvar(r), [r])
    rng = np.random.default_rng(0)
    for _ in range(3):
        val = float(f(*[rng.uniform(0.5, 2.0) for _ in range(f.n_in())]))
        if abs(val) > 1e-12:
            return False
    return True


# -- matching and BLT ----------------------------------------------------------------
def _solve_blt(eqs, unknowns, labels):
    n_e, n_u = len(eqs), len(unknowns)
    R = ca.vertcat(*[r for r, _ in eqs]) if eqs else ca.SX(0, 1)
    U = ca.vertcat(*unknowns) if unknowns else ca.SX(0, 1)
    sp = ca.jacobian(R, U).sparsity() if n_e and n_u else None
    if sp is not None:
        rows, cols = sp.get_triplet()
        inc = csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_e, n_u))
    else:
        inc = csr_matrix((n_e, n_u))
    match = maximum_bipartite_matching(inc, perm_type="column") if n_e and n_u else np.full(n_e, -1)
    matched_u = set(int(j) for j in match if j >= 0)
    left_eq = [eqs[i][1] for i in range(n_e) if match[i] < 0]
    left_u = [labels[j] for j in range(n_u) if j not in matched_u]
    if left_eq or left_u:
        msg = []
        if left_u:
            msg.append("under-determined: no equation determines "
                       + ", ".join(left_u)
                       + " (is a flange left unconnected, or a component missing?)")
        if left_eq:
            msg.append("over-determined: nothing is left for "
                       + "; ".join(left_eq))
        if left_u and left_eq:
            msg.append("(the counts match but the structure is singular: "
                       "a constraint between states, i.e. a high-index DAE)")
        raise ModelError("\n".join(msg))

    # BLT: graph eq -> eq (the equation that determines an unknown it uses)
    eq_of_u = {int(j): i for i, j in enumerate(match)}
    r_idx, c_idx = inc.nonzero()
    dst = [eq_of_u[int(c)] for c in c_idx]
    g = csr_matrix((np.ones(len(r_idx)), (r_idx, dst)), shape=(n_e, n_e))
    n_blocks, lab = connected_components(g, directed=True, connection="strong")
    deps = {b: set() for b in range(n_blocks)}
    for a, b in zip(r_idx, dst):
        if lab[a] != lab[b]:
            deps[lab[a]].add(lab[b])
    order = list(graphlib.TopologicalSorter(deps).static_order())

    solved = []          # (unknown symbol, expression in x, z, p, t)
    z_syms, z_labels, alg = [], [], []
    for b in order:
        rows = [i for i in range(n_e) if lab[i] == b]
        block_u = [unknowns[int(match[i])] for i in rows]
        Rb = ca.vertcat(*[eqs[i][0] for i in rows])
        if solved:
            Rb = _subst(Rb, ca.vertcat(*[s for s, _ in solved]),
                        ca.vertcat(*[e for _, e in solved]))
        Ub = ca.vertcat(*block_u)
        A = ca.jacobian(Rb, Ub)
        if not ca.depends_on(A, Ub) and len(rows) <= 12:
            rhs = -ca.substitute(Rb, Ub, ca.DM.zeros(len(rows)))
            sol = rhs / A if len(rows) == 1 else ca.solve(A, rhs)
            solved.extend((block_u[k], sol[k]) for k in range(len(rows)))
        else:
            z_syms.extend(block_u)
            z_labels.extend(labels[int(match[i])] for i in rows)
            alg.extend(Rb[k] for k in range(len(rows)))
    return solved, z_syms, z_labels, alg


def _check_consistent_start(flat, al, states, x0, p_sym, free, final, t):
    """A state eliminated as an alias must start where its replacement starts
    (checked at the default parameter values)."""
    gone = [(v, where) for v, _, where in al.states_gone if v.is_state or v.start is not None]
    if not gone:
        return
    x = ca.vertcat(*[v.sym for v in states]) if states else ca.SX(0, 1)
    mine = ca.vertcat(*[_start(v) for v, _ in gone])
    theirs = ca.vertcat(*[_subst(final(v.sym), x, x0) for v, _ in gone])
    f = ca.Function("start_check", [t, p_sym], [mine, theirs])
    a, b = (np.array(r).ravel() for r in f(0.0, [p.value for p in free]))
    for (v, where), s_mine, s_theirs in zip(gone, a, b):
        if abs(s_mine - s_theirs) > 1e-9 * (1.0 + abs(s_mine)):
            raise ModelError(
                f"{v.name} starts at {s_mine:g} {v.unit}, but {where} ties it to a value "
                f"that starts at {s_theirs:g} {v.unit}; give rigidly connected bodies "
                "consistent start values")
