"""Alias elimination: equations ``a*u + b*w + c(p, t) = 0`` (a a number, b a
number or a parameter expression; or ``a*u + c(p, t) = 0``) remove ``u`` from
the system, derivatives included: eliminating ``u`` also replaces ``der(u)``
by the derivative of its replacement, so a state tied to another state stops
being a state (two rigidly connected masses become one mass). Where no
number-coefficient edge reaches a member, a coefficient made of parameters
declared positive serves (two pistons on one incompressible line:
``A1*v1 + A2*v2 = 0``).

Near-linear in the size of the rig: the alias equations are found in bulk
(one Jacobian sparsity, one test of linearity), joined into alias sets
(union-find), and each set is expressed in its most important member - a
declared state first, then a variable whose derivative is used, then a
component's variable before a connector's, the first declared before later
ones - by one walk over the set. Every replacement is then a function of
the kept members only, so the equations are substituted once. New aliases
made by that substitution (an equation left with two unknowns) are found in
the next round; there are rarely more than two.
"""
from __future__ import annotations

from collections import deque

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix

from pdbfs.errors import ModelError

from ..casadi_helpers import subst as _subst
from ..rig_inputs import refuse_second_derivative


class Aliases:
    """The alias sets of one flat system and the replacements found so far."""

    def __init__(self, flat, t):
        self.t = t
        self.vars = {v.name: v for v in flat.vars}
        self.order = {v.name: i for i, v in enumerate(flat.vars)}
        self.der_owner = {v.der.name(): v for v in flat.vars if v.der is not None}
        self.K, self.V = [], []              # eliminated symbols and their replacements
        self.gone: set[str] = set()
        self.used_der: set[str] = set(self.der_owner)
        self.states_gone: list[tuple] = []   # (FlatVar, replacement, equation's origin)
        self._KV = None
        self.nonzero = nonzero_by({p.name for p in flat.params if p.decl.positive})
        # an input's slope: its derivative within a segment, not to be differentiated again
        self.input_slopes = {i.slope.name(): i.name for i in getattr(flat, "inputs", ())}
        self.jumps = None                    # smoothness.Jumps: what is differentiated is tested

    # -- ranks ------------------------------------------------------------------
    def rank(self, name):
        """(rank, -order) of a variable-like symbol: the larger is kept."""
        v = self.vars.get(name)
        if v is not None:
            if v.is_state:
                r = 4
            elif v.der is not None and v.der.name() in self.used_der:
                r = 3
            else:
                r = v.rank - 1       # component variable 1, connector variable 0
            return (r, -self.order[name])
        return (2, -self.order[self.der_owner[name].name])

    def unknown_symbols(self):
        """The symbols of the unknowns not eliminated (unknowns())."""
        return [s for _, s in self.unknowns()]

    def unknowns(self):
        """(name, symbol) of every variable and der() symbol not eliminated
        (cached until the next elimination)."""
        key = (len(self.gone), len(self.der_owner))
        if getattr(self, "_unknowns_key", None) != key:
            gone = self.gone
            out = [(n, v.sym) for n, v in self.vars.items() if n not in gone]
            out += [(d, v.der) for d, v in self.der_owner.items() if d not in gone]
            self._unknowns, self._unknowns_key = out, key
            self._unknowns_vec = None
        return self._unknowns

    def unknowns_vector(self):
        """The unknowns not eliminated as one CasADi column (cached with unknowns())."""
        self.unknowns()
        if self._unknowns_vec is None:
            self._unknowns_vec = ca.vertcat(*[u for _, u in self._unknowns])
        return self._unknowns_vec

    # -- elimination ---------------------------------------------------------------
    def eliminate(self, eqs):
        """The residuals of ``eqs`` ((residual, origin) pairs) left after removing their aliases."""
        R = ca.vertcat(*[r for r, _ in eqs]) if eqs else ca.SX(0, 1)   # one column
        W = [w for _, w in eqs]
        fresh = None                     # rows that may have become aliases (None: all)
        while True:                      # a round can leave new aliases behind
            edges, rest = self._classify(R, self.unknowns(), fresh)
            if not edges:
                break
            keys, vals, rows = self._round(edges, W)
            if not keys:                 # aliases that cannot be solved: plain equations
                break
            W = [W[i] for i in rest] + [w for _, w in rows]
            kept = R[rest] if rest else ca.SX(0, 1)
            K, V = ca.vertcat(*keys), ca.vertcat(*vals)
            touched = _rows_with(kept, K)
            fresh = set(touched) | set(range(kept.numel(), kept.numel() + len(rows)))
            R = self._apply(ca.vertcat(kept, *[r for r, _ in rows]), keys, vals, K, V)
        kept = []
        unknown = {n for n, _ in self.unknowns()}
        for r, where in zip(ca.vertsplit(R, 1) if R.numel() else [], W):
            if not any(s.name() in unknown for s in ca.symvar(r)):
                if _identically_zero(r):
                    continue
                raise ModelError(f"over-determined: {where} leaves nothing to determine "
                                 f"(0 = {r}); a redundant connection or a constraint on fixed values?")
            kept.append((r, where))
        return kept

    def _classify(self, R, unknowns, fresh=None):
        """(alias edges, indices of the other equations). An edge is (row,
        [(symbol name, coefficient, its number or None)], constant part).
        Only the rows in ``fresh`` (all if None) are looked at."""
        n_r = R.numel()
        look = list(range(n_r)) if fresh is None else sorted(fresh)
        if not look or not unknowns:
            return [], list(range(n_r))
        names = [n for n, _ in unknowns]
        Rv, Uv = R[look], self.unknowns_vector()
        rows, cols = ca.jacobian_sparsity(Rv, Uv).get_triplet()
        inc = csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(look), len(names)))
        count = np.diff(inc.indptr)
        cand = np.flatnonzero((count >= 1) & (count <= 2))
        if cand.size == 0:
            return [], list(range(n_r))
        Rc = Rv[[int(i) for i in cand]]
        nonlinear = ca.which_depends(Rc, Uv, 2, True)
        J = ca.jacobian(Rc, Uv)
        c0 = ca.vertsplit(ca.substitute(Rc, Uv, ca.DM.zeros(len(names))), 1)
        # the coefficients: J's nonzeros, by (row, column), in one call
        jr, jc = J.sparsity().get_triplet()
        coef = {}
        for r, c, v in zip(jr, jc, J.nonzeros()):
            coef[(r, c)] = v
        in_time = ca.which_depends(ca.vertcat(*J.nonzeros()), self.t, 1, True) \
            if J.nnz() else []
        timed = {(r, c) for r, c, d in zip(jr, jc, in_time) if d}
        edges, alias_rows = [], set()
        for k, i in enumerate(cand):
            if nonlinear[k]:
                continue
            cs = inc.indices[inc.indptr[i]:inc.indptr[i + 1]]
            if any((k, int(j)) in timed for j in cs):
                continue                 # coefficients must not change in time
            terms = [_term(names[int(j)], coef.get((k, int(j)), ZERO)) for j in cs]
            edges.append((look[int(i)], terms, c0[k]))
            alias_rows.add(look[int(i)])
        return edges, [i for i in range(n_r) if i not in alias_rows]

    def _round(self, edges, W):
        """One round: every alias set expressed in its best member. Returns the
        eliminated symbols, their replacements, and rows to keep: equations
        closing a cycle of aliases, and derivatives that cannot be eliminated
        directly (checked or used in the next round)."""
        sym = dict(self.unknowns())
        keys, vals, rows, eliminated = [], [], [], []
        for members, set_edges in _components(edges):
            by_node = {}
            for e in set_edges:
                for name, *_ in e[1]:
                    by_node.setdefault(name, []).append(e)
            expr, tree = self._express(members, set_edges, by_node, sym)
            for name, value in expr.items():
                if _is_symbol(value, name):
                    continue
                keys.append(sym[name])
                vals.append(value)
                eliminated.append((name, value, W[by_node[name][0][0]]))
            for e in set_edges:          # equations closing a cycle: kept, checked later
                if e[0] not in tree:
                    rows.append((sum((c * sym[n] for n, c, _ in e[1]), e[2]), W[e[0]]))
        in_sets = {k.name() for k in keys} | {n for m, _ in _components(edges) for n in m}
        der_keys, der_vals = [], []
        for name, value, where in eliminated:
            v = self.vars.get(name)
            if v is None:
                continue
            if v.is_state or (v.der is not None and v.der.name() in self.used_der):
                self.states_gone.append((v, value, where))
            if v.der is not None and v.der.name() not in self.gone:
                d = self._derivative(value)
                if v.der.name() in in_sets:      # der(u) is an alias itself: keep the relation
                    rows.append((v.der - d, f"derivative of {where}"))
                else:
                    der_keys.append(v.der)
                    der_vals.append(d)
        if der_keys and keys:            # derivatives in terms of this round's survivors
            dv = _subst(ca.vertcat(*der_vals), ca.vertcat(*keys), ca.vertcat(*vals))
            der_vals = ca.vertsplit(dv, 1)
        return keys + der_keys, vals + der_vals, rows

    def _express(self, members, set_edges, by_node, sym):
        """(name -> replacement, tree edges) of one alias set: from a member
        fixed by a parameter expression if there is one, else from the best
        member from which every other one can be reached."""
        fixed, tree = {}, set()
        for e in set_edges:              # members fixed by parameter expressions: all of them,
            if len(e[1]) == 1:           # so that a cycle is closed by a connection (named)
                (name, a, f), = e[1]
                if f and name not in fixed:
                    fixed[name] = -e[2] / f
                    tree.add(e[0])
        if fixed:
            return _walk(fixed, by_node, tree, self.nonzero)
        best = None
        for cand in sorted(members, key=self.rank, reverse=True):
            trial = _walk({cand: sym[cand]}, by_node, set(), self.nonzero)
            if best is None or len(trial[0]) > len(best[0]):
                best = trial
            if len(trial[0]) == len(members):
                break
        return best

    def _derivative(self, value):
        """d/dt of a replacement (linear in kept members), through their der symbols."""
        if value.is_symbolic() and value.name() in self.vars:      # the usual u = w
            v = self._with_der(self.vars[value.name()])
            return self.resolve(v.der)
        refuse_second_derivative(value, self.input_slopes, self.t)
        if self.jumps is not None:     # a replacement may be a derivative already: level unknown
            self.jumps.look(value, None)
        out = ca.jacobian(value, self.t)
        for s in ca.symvar(value):
            n = s.name()
            if n in self.der_owner:
                raise ModelError(f"the rig needs the second derivative of {self.der_owner[n].name}: "
                                 "index reduction of that order is not supported")
            v = self.vars.get(n)
            if v is None:
                continue                 # a parameter
            out = out + ca.jacobian(value, s) * self._with_der(v).der
        return self.resolve(out)         # der(w) may have been eliminated in an earlier round

    def _with_der(self, v):
        """v, with a der() symbol made and marked used."""
        if v.der is None:
            v.der = ca.SX.sym(f"der({v.name})")
            self.der_owner[v.der.name()] = v
        self.used_der.add(v.der.name())
        return v

    def _apply(self, R, keys, vals, K, V):
        """Record the eliminations (K, V: keys and vals as columns) and
        substitute them into the column R, once."""
        for k in keys:
            self.gone.add(k.name())
        self.K.append(K)
        self.V.append(V)
        self._KV = None
        if not R.numel() or not keys:
            return R
        return _subst(R, K, V)

    def resolve(self, expr):
        """``expr`` with every eliminated symbol replaced by its kept members."""
        if self._KV is None:
            self._KV = self._closed()
        K, V = self._KV
        return _subst(expr, K, V)

    def _closed(self):
        """Replacements in terms of surviving symbols only (later rounds may
        have eliminated what earlier replacements refer to)."""
        if not self.K:
            return ca.SX(0, 1), ca.SX(0, 1)
        K, V = ca.vertcat(*self.K), ca.vertcat(*self.V)     # one block per round
        for _ in range(len(self.K) + 1):
            if not ca.depends_on(V, K):
                break
            V = _subst(V, K, V)
        return K, V


ZERO = ca.SX(0)


def _term(name, c):
    """(name, coefficient, its value if it is a number else None)."""
    return name, c, float(c) if c.is_constant() else None


def _rows_with(R, K) -> list[int]:
    """Indices of the rows of the column R that contain any of the symbols in K."""
    if not R.numel() or not K.numel():
        return []
    rows, _ = ca.jacobian_sparsity(R, K).get_triplet()
    return sorted(set(rows))


def _is_symbol(value, name) -> bool:
    return isinstance(value, ca.SX) and value.is_symbolic() and value.name() == name


def _walk(expr, by_node, tree, nonzero=None):
    """Express every member reachable from the known ones, each through an
    edge where its own coefficient is a non-zero number; where none is left,
    through an edge whose coefficient ``nonzero(c)`` proves non-zero (a
    product of positive parameters: two pistons of areas A1, A2 on one
    incompressible line, A1*v1 + A2*v2 = 0)."""
    tree = set(tree)
    expr = dict(expr)
    queue = deque(expr)
    later = []                           # edges with a symbolic coefficient on u
    while True:
        while queue:
            w = queue.popleft()
            for e in by_node.get(w, ()):
                if e[0] in tree or len(e[1]) != 2:
                    continue
                (n1, a1, f1), (n2, a2, f2) = e[1]
                u, a_u, f_u, a_w, f_w = (n2, a2, f2, a1, f1) if n1 == w else (n1, a1, f1, a2, f2)
                if u in expr or f_w == 0.0:
                    continue
                if not f_u:
                    if f_u is None and nonzero is not None:
                        later.append((e, w, u, a_u, a_w))
                    continue
                if f_w is not None and e[2].is_zero():     # u = factor * w: most aliases
                    factor = -f_w / f_u
                    expr[u] = expr[w] if factor == 1.0 else factor * expr[w]
                else:
                    expr[u] = -(a_w * expr[w] + e[2]) / f_u
                tree.add(e[0])
                queue.append(u)
        while later and not queue:
            e, w, u, a_u, a_w = later.pop(0)
            if u in expr or e[0] in tree or not nonzero(a_u):
                continue
            expr[u] = -(a_w * expr[w] + e[2]) / a_u
            tree.add(e[0])
            queue.append(u)
        if not queue:
            return expr, tree


def nonzero_by(positive: set):
    """A test that a coefficient is non-zero whatever the parameters' values:
    built from non-zero numbers and parameters declared positive by
    products, quotients, negation and square roots."""
    ops = {ca.OP_NEG, ca.OP_MUL, ca.OP_DIV, ca.OP_SQRT, ca.OP_SQ, ca.OP_TWICE, ca.OP_INV}

    def check(c) -> bool:
        if c.is_constant():
            return float(c) != 0.0
        if c.is_symbolic():
            return c.name() in positive
        return c.op() in ops and all(check(c.dep(i)) for i in range(c.n_dep()))
    return check


def _components(edges):
    """The alias sets: [(members, edges)] per connected set (scipy's
    connected components of the graph of the edges)."""
    from scipy.sparse.csgraph import connected_components
    index, a, b = {}, [], []
    for e in edges:
        names = [n for n, *_ in e[1]]
        ks = [index.setdefault(n, len(index)) for n in names]
        a.append(ks[0])
        b.append(ks[-1])
    n = len(index)
    graph = csr_matrix((np.ones(len(a)), (a, b)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    groups = {}
    names = list(index)
    for k, lab in enumerate(label):
        groups.setdefault(int(lab), ([], []))[0].append(names[k])
    for e, i in zip(edges, a):
        groups[int(label[i])][1].append(e)
    return list(groups.values())


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
