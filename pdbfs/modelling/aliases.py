"""Alias elimination: equations ``a*u + b*w + c(p, t) = 0`` (a a number, b a
number or a parameter expression) remove ``u`` from the system, derivatives
included: eliminating ``u`` also replaces ``der(u)`` by the derivative of its
replacement, so a state tied to another state stops being a state (two
rigidly connected masses become one mass).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError

from .symbolic import subst as _subst


class Aliases:
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
