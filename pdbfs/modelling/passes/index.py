"""Index reduction: Pantelides' algorithm (SIAM J. Sci. Stat. Comput. 9(2),
1988) with dummy derivatives (Mattsson and Soderlind, SIAM J. Sci. Comput.
14(3), 1993), to any index.

Used only where matching failed after alias elimination. Pantelides: the
equations that are matched on the highest derivatives only; the
over-determined part (the equations reached from an unmatched one by
alternating paths) is differentiated, every variable in it is replaced by
its derivative (a new unknown where it had none: derivatives of derivatives
too), and the matching is tried again, as often as needed. Dummy
derivatives: per differentiation level, from the highest down, as many of
the highest derivatives as there are differentiated equations are chosen
so that those equations can be solved for them (structurally, then
numerically at the start values; new derivatives of algebraic variables
first, then states of lower alias rank), and the states they integrate into
become algebraic. All equations, differentiated or not, stay: the result is
an index-1 DAE for IDAS (often an ODE after BLT), and the constraints hold
along the solution. One level of differentiation is the special case of the
two-volume and two-piston rigs.

A state whose derivative alias elimination replaced by an expression (a
piston's position, der = -A2/A1*v2 on an incompressible line) gets its own
der() unknown and that replacement as an equation, so that the algorithm can
differentiate it further and make the position algebraic (a cam driving a
massless piston).
"""
from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import maximum_bipartite_matching

from pdbfs.errors import ModelError

from ..rig_inputs import refuse_second_derivative

ALIAS_DER = " by alias elimination"
MAX_LEVEL = 8        # a structurally singular system would be differentiated for ever


def reduce_index(eqs, unknowns, labels, states, algebraic, al, t, start=None):
    """(equations, unknowns, labels, remaining states, the labels of the
    constraints differentiated) with the singular part
    differentiated as often as needed and dummy derivatives chosen, or None
    where Pantelides' algorithm finds no regular system. ``start`` is
    (name -> start value, parameter symbols, their values) for the numerical
    check of the chosen dummy derivatives. Raises ModelError where the only
    choice is numerically singular at the start values."""
    if not overdetermined(eqs, unknowns):
        return None
    p = _Pantelides(eqs, unknowns, states, algebraic, al, t)
    if not p.run():
        return None
    return p.dummy_derivatives(labels, states, start)


class _Pantelides:
    def __init__(self, eqs, unknowns, states, algebraic, al, t):
        self.al, self.t = al, t
        self.eqs = list(eqs)
        self.parent = [None] * len(eqs)
        self.level = [0] * len(eqs)
        self.child = [None] * len(eqs)
        self.unknowns = list(unknowns)
        self.highest = list(unknowns)            # the unknowns Pantelides matches on
        self.slot = {u.name(): k for k, u in enumerate(self.highest)}
        self.state_of = {v.name: v for v in states}
        self.variables = {v.name for v in algebraic} | {u.name() for u in unknowns}
        self.succ, self.pred, self.new = {}, {}, []
        # a state integrates its der() symbol, or the symbol its derivative is an alias of
        self.integrates = {}
        self.own_der, self.own_labels = {}, []
        for v in states:
            d = v.der if v.der.name() not in al.gone else al.resolve(v.der)
            if d.is_symbolic() and d.name() != v.name and d.name() not in self.integrates:
                self.integrates[d.name()] = v
        have = {id(w) for w in self.integrates.values()}
        for v in states:
            if id(v) in have:
                continue
            # its derivative was eliminated as a scaled alias (a piston's position,
            # der = -A2/A1*v2): it gets its own der() unknown and the alias as an
            # equation, so that the reducer can differentiate it further and make the
            # position algebraic (a cam driving a massless piston)
            d = ca.SX.sym(f"der({v.name})")
            self.integrates[d.name()] = v
            self.own_der[v.name] = d
            self.eqs.append((d - al.resolve(v.der), f"der({v.name}){ALIAS_DER}"))
            self.parent.append(None)
            self.level.append(0)
            self.child.append(None)
            self.slot[d.name()] = len(self.highest)
            self.unknowns.append(d)
            self.highest.append(d)
            self.own_labels.append(d.name())
            self.variables.add(d.name())

    def run(self) -> bool:
        while True:
            active = [i for i in range(len(self.eqs)) if self.child[i] is None]
            block = overdetermined([self.eqs[i] for i in active], self.highest)
            if not block:
                return True
            for i in (active[k] for k in block):
                if self.level[i] >= MAX_LEVEL:
                    return False
                r, _ = self.eqs[i]
                self.child[i] = len(self.eqs)
                self.parent.append(i)
                self.level.append(self.level[i] + 1)
                self.child.append(None)
                self.eqs.append((self._diff(r, self.level[i]), self._label(i)))

    def _label(self, i):
        n, root = self.level[i] + 1, i
        while self.parent[root] is not None:
            root = self.parent[root]
        what = {1: "derivative", 2: "second derivative", 3: "third derivative"}.get(
            n, f"derivative {n}")
        return f"{what} of {self.eqs[root][1]} (index reduction)"

    def _diff(self, r, level):
        """d/dt of r (differentiated ``level`` times already), through the
        derivatives of the symbols in it (an input's slope is constant over a
        segment; a switch of time must not jump: smoothness.py)."""
        refuse_second_derivative(r, self.al.input_slopes, self.t)
        if self.al.jumps is not None:
            self.al.jumps.look(r, level)
        d = ca.jacobian(r, self.t)
        for s in ca.symvar(r):
            ds = self._derivative_of(s)
            if ds is not None:
                d = d + ca.jacobian(r, s) * ds
        return self.al.resolve(d)

    def _derivative_of(self, s):
        n = s.name()
        if n in self.own_der:
            return self.own_der[n]
        if n in self.state_of:
            return self.state_of[n].der
        if n in self.succ:
            return self.succ[n]
        if n not in self.variables:
            return None                      # a parameter
        d = ca.SX.sym(f"der({n})")
        self.succ[n], self.pred[d.name()] = d, s
        self.new.append(d)
        self.variables.add(d.name())
        if n in self.slot:                   # the derivative replaces it in the matching
            k = self.slot.pop(n)
            self.highest[k] = d
            self.slot[d.name()] = k
        return d

    # -- dummy derivatives ------------------------------------------------------------
    def _before(self, u):
        """What the derivative u is the derivative of (a symbol), or None."""
        n = u.name()
        if n in self.pred:
            return self.pred[n]
        v = self.integrates.get(n)
        return v.sym if v is not None else None

    def _state_of_derivative(self, u):
        """The name of the state whose derivative (or higher) u is, else u's name."""
        s = u
        while s.name() in self.pred:
            s = self.pred[s.name()]
        v = self.integrates.get(s.name())
        return v.name if v is not None else s.name()

    def _preference(self, u):
        """Dummies are chosen in this order: new derivatives of algebraic
        variables (so that no new state appears), then derivatives along the
        states of lower alias rank (the higher ones stay states)."""
        s = u
        while s.name() in self.pred:
            s = self.pred[s.name()]
        v = self.integrates.get(s.name()) or self.state_of.get(s.name())
        if u.name() in self.pred and (v is None or v.name in self.own_der):
            return (0, ([d.name() for d in self.new].index(u.name()),))
        if v is not None and v.name in self.own_der:
            return (0, (-1,))                # an alias's position: algebraic before a state
        return (1, self.al.rank(v.name)) if v is not None else (2, (0,))

    def dummy_derivatives(self, labels, states, start):
        g = [i for i in range(len(self.eqs)) if self.child[i] is None and self.level[i] >= 1]
        cand = [u for u in self.highest if self._before(u) is not None]
        picked = []
        while g:
            R = ca.vertcat(*[self.eqs[i][0] for i in g])
            inside = {x.name() for x in ca.symvar(R)}
            order = sorted((u for u in cand if u.name() in inside), key=self._preference)
            pick = _choose(R, order, len(g), start, [self.eqs[i][1] for i in g],
                           [self._state_of_derivative(u) for u in order])
            if pick is None:
                return None
            picked += pick
            g = [self.parent[i] for i in g if self.level[self.parent[i]] >= 1]
            cand = [b for b in (self._before(d) for d in pick) if b is not None
                    and self._before(b) is not None]
        names = {d.name() for d in picked}
        if any(d.name() not in names for d in self.new):
            return None                      # it would make a new state without a start value
        made_algebraic = [self.integrates[d.name()] for d in picked if d.name() in self.integrates]
        gone = {id(v) for v in made_algebraic}
        return (self.eqs, self.unknowns + self.new + [v.sym for v in made_algebraic],
                list(labels) + self.own_labels + [d.name() for d in self.new]
                + [v.name for v in made_algebraic],
                [v for v in states if id(v) not in gone],
                [self.eqs[i][1] for i in range(len(self.eqs))
                 if self.level[i] == 0 and self.child[i] is not None
                 and not self.eqs[i][1].endswith(ALIAS_DER)])


def _choose(R, cand, need, start, where, owners):
    """``need`` of the candidates (in order of preference) for which the
    Jacobian of R is nonsingular: structurally first (greedy over the
    preference), then checked at the start values, where a singular choice
    is replaced by a greedy numerical one; None if there is no structural
    choice; ModelError if there is no numerical one."""
    picked = []
    for u in cand:
        if len(picked) == need:
            break
        if _structural_rank(R, picked + [u]) == len(picked) + 1:
            picked.append(u)
    if len(picked) != need:
        return None
    if start is None or not cand:
        return picked
    H = _at_start(ca.jacobian(R, ca.vertcat(*cand)), start)
    col = {u.name(): k for k, u in enumerate(cand)}
    if _rank(H[:, [col[u.name()] for u in picked]]) == need:
        return picked
    picked = []
    for u in cand:
        if len(picked) < need and _rank(H[:, [col[w.name()] for w in picked + [u]]]) == len(picked) + 1:
            picked.append(u)
    if len(picked) == need:
        return picked
    raise ModelError(
        f"index reduction: {'; '.join(dict.fromkeys(where))} cannot be solved for {need} of "
        f"{', '.join(u.name() for u in cand)} (states {', '.join(dict.fromkeys(owners))}): "
        "numerically singular at the start values (a constraint at a dead point?); start the "
        "rig away from it")


def _at_start(H, start):
    """H (a matrix of expressions) at the start values: declared starts of
    the variables, 0 for the rest, default parameter values."""
    start_of, p_sym, p_val = start
    params = {p_sym[k].name() for k in range(p_sym.numel())}
    syms = [s for s in ca.symvar(H) if s.name() not in params]
    if syms:
        vals = [ca.SX(start_of.get(s.name(), 0.0)) for s in syms]
        H = ca.substitute(H, ca.vertcat(*syms), ca.vertcat(*vals))
    f = ca.Function("H0", [p_sym], [ca.densify(H)])
    return np.array(f(p_val), dtype=float).reshape(H.shape)


def _rank(H) -> int:
    if H.size == 0:
        return 0
    sv = np.linalg.svd(H, compute_uv=False)
    return int(np.sum(sv > 1e-10 * max(1.0, sv.max())))


def overdetermined(eqs, unknowns) -> list[int]:
    """Equations reached from an unmatched one by alternating paths."""
    R, U = ca.vertcat(*[r for r, _ in eqs]), ca.vertcat(*unknowns)
    rows, cols = ca.jacobian_sparsity(R, U).get_triplet()
    inc = csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(eqs), len(unknowns)))
    match = maximum_bipartite_matching(inc, perm_type="column")
    eq_of = {int(j): i for i, j in enumerate(match) if j >= 0}
    block, todo = set(), [i for i in range(len(eqs)) if match[i] < 0]
    while todo:
        i = todo.pop()
        if i in block:
            continue
        block.add(i)
        todo += [eq_of[int(j)] for j in inc.indices[inc.indptr[i]:inc.indptr[i + 1]]
                 if int(j) in eq_of]
    return sorted(block)


def _structural_rank(R, syms) -> int:
    if not syms:
        return 0
    rows, cols = ca.jacobian_sparsity(R, ca.vertcat(*syms)).get_triplet()
    inc = csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(R.numel(), len(syms)))
    return int(np.sum(maximum_bipartite_matching(inc, perm_type="column") >= 0))
