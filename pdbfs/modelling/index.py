"""Index reduction of one level: Pantelides' differentiation of the
structurally singular equations, with dummy derivatives (Mattsson and
Soderlind, SIAM J. Sci. Comput. 14(3), 1993) to keep the system square.

Used only where matching failed after alias elimination. The over-determined
part of the equations (those reached from an unmatched one by alternating
paths, as Pantelides' augmenting-path search colours them) is differentiated
once; the new highest derivatives of algebraic variables become dummy
derivatives, and so do the derivatives of as many states as are needed to
make the differentiated equations solvable for them (structurally; states of
lower alias rank first): those states become algebraic. The result is an
index-1 DAE for IDAS. A second differentiation (index 3 and above), or
equations that already hold derivatives, are not reduced: the caller then
refuses the rig.
"""
from __future__ import annotations

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import maximum_bipartite_matching


def reduce_index(eqs, unknowns, labels, states, algebraic, al, t):
    """(equations, unknowns, labels, remaining states) with the singular part
    differentiated once and dummy derivatives chosen, or None where this
    one-level reduction does not apply."""
    block = overdetermined(eqs, unknowns)
    if not block:
        return None
    der_syms = {v.der.name() for v in states if v.der is not None}
    state_of = {v.name: v for v in states}
    alg_of = {v.name: v for v in algebraic}
    new_der, diffed = {}, []
    for i in block:
        r, where = eqs[i]
        d = ca.jacobian(r, t)
        for s in ca.symvar(r):
            n = s.name()
            if n in der_syms:
                return None                         # would need second derivatives
            if n in state_of:
                d = d + ca.jacobian(r, s) * state_of[n].der
            elif n in alg_of:
                if n not in new_der:
                    new_der[n] = ca.SX.sym(f"der({n})")
                d = d + ca.jacobian(r, s) * new_der[n]
        diffed.append((al.resolve(d), f"derivative of {where} (index reduction)"))
    # dummy derivatives: every new one, then states' until the block is solvable
    cand = list(new_der.values())
    need = len(diffed) - len(cand)
    if need < 0:
        return None
    in_block = {s.name() for r, _ in diffed for s in ca.symvar(r)}
    by_rank = sorted((v for v in states if v.der is not None and v.der.name() in in_block
                      and v.der.name() not in al.gone), key=lambda v: al.rank(v.name))
    dummies = []
    R = ca.vertcat(*[r for r, _ in diffed])
    for v in by_rank:
        if len(dummies) == need:
            break
        trial = cand + [w.der for w in dummies] + [v.der]
        if _structural_rank(R, trial) == len(trial):
            dummies.append(v)
    if len(dummies) != need or _structural_rank(R, cand + [w.der for w in dummies]) != len(diffed):
        return None
    gone_states = {id(v) for v in dummies}
    unknowns = list(unknowns) + list(new_der.values()) + [v.sym for v in dummies]
    labels = list(labels) + [f"der({n})" for n in new_der] + [v.name for v in dummies]
    kept = [v for v in states if id(v) not in gone_states]
    return list(eqs) + diffed, unknowns, labels, kept


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
