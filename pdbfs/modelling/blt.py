"""Matching and block-lower-triangular (BLT) sorting of the equations left
after alias elimination; each block linear in its unknowns is solved
symbolically, nonlinear blocks stay algebraic (IDAS solves them).
"""
from __future__ import annotations

import graphlib

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components, maximum_bipartite_matching

from pdbfs.errors import ModelError

from .symbolic import subst as _subst


def solve_blt(eqs, unknowns, labels):
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
