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

from ..casadi_helpers import subst as _subst


def solve_blt(eqs, unknowns, labels, pivots=None):
    """Match ``eqs`` ((residual, origin) pairs) to ``unknowns`` (symbols named
    ``labels``) and solve them block by block in BLT order. Returns (solved
    (symbol, expression) pairs, algebraic symbols, their names, their residuals);
    raises ModelError naming what is under- or over-determined. ``pivots``
    (a list), where given, receives (pivot, the equations' origins) of every
    linear block solved symbolically: its solution divides by the pivot
    (an algebraic loop y = 1 + k y by 1 - k), which must not be 0."""
    pivots = [] if pivots is None else pivots
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

    members = np.argsort(lab, kind="stable")
    starts = np.searchsorted(lab[members], np.arange(n_blocks + 1))
    rows_of = lambda b: [int(i) for i in members[starts[b]:starts[b + 1]]]   # noqa: E731
    # levels: a block comes after every block it needs; a level's blocks of one
    # equation are solved together (a chain of masses is a few levels deep)
    level = np.zeros(n_blocks, dtype=int)
    for b in order:
        level[b] = 1 + max((level[d] for d in deps[b]), default=-1)
    known = {}           # name of a solved unknown -> its expression in x, z, p, t
    solved, result = [], {}
    for lv in range(int(level.max()) + 1 if n_blocks else 0):
        blocks = [b for b in order if level[b] == lv]
        single = [b for b in blocks if starts[b + 1] - starts[b] == 1]
        for b in [b for b in blocks if starts[b + 1] - starts[b] > 1]:
            result[b] = _solve_block(b, rows_of(b), eqs, unknowns, match, labels, known, solved,
                                     pivots)
        if single:
            _solve_singles(single, rows_of, eqs, unknowns, match, labels, known, solved, result,
                           pivots)
    z_syms, z_labels, alg = [], [], []
    for b in order:                      # algebraic unknowns in the order of the blocks
        zs, zl, al = result.get(b, ([], [], []))
        z_syms += zs
        z_labels += zl
        alg += al
    return solved, z_syms, z_labels, alg


def _known_in(R, known):
    """R with the expressions of the unknowns solved earlier put in."""
    inside = [s for s in ca.symvar(R) if s.name() in known]
    if not inside:
        return R
    return _subst(R, ca.vertcat(*inside), ca.vertcat(*[known[s.name()] for s in inside]))


def _solve_block(b, rows, eqs, unknowns, match, labels, known, solved, pivots):
    """One block of several equations: solved if linear (and small), else algebraic."""
    block_u = [unknowns[int(match[i])] for i in rows]
    Rb = _known_in(ca.vertcat(*[eqs[i][0] for i in rows]), known)
    Ub = ca.vertcat(*block_u)
    A = ca.jacobian(Rb, Ub)
    if not ca.depends_on(A, Ub) and len(rows) <= 12:
        rhs = -ca.substitute(Rb, Ub, ca.DM.zeros(len(rows)))
        sol = ca.solve(A, rhs)
        if len(rows) <= 4:          # (a determinant of more is not worth its expression)
            pivots.append((ca.det(A), [eqs[i][1] for i in rows]))
        for k in range(len(rows)):
            solved.append((block_u[k], sol[k]))
            known[block_u[k].name()] = sol[k]
        return [], [], []
    return block_u, [labels[int(match[i])] for i in rows], ca.vertsplit(Rb, 1)


def _solve_singles(blocks, rows_of, eqs, unknowns, match, labels, known, solved, result,
                   pivots):
    """Blocks of one equation each, independent of each other: solved in bulk
    where linear in their unknown, algebraic where not."""
    rows = [rows_of(b)[0] for b in blocks]
    us = [unknowns[int(match[i])] for i in rows]
    R = _known_in(ca.vertcat(*[eqs[i][0] for i in rows]), known)
    U = ca.vertcat(*us)
    nonlinear = ca.which_depends(R, U, 2, True)
    J = ca.jacobian(R, U)
    diag = {}
    for r, c, v in zip(*J.sparsity().get_triplet(), J.nonzeros()):
        if r == c:
            diag[r] = v
    sol = ca.vertsplit(-ca.substitute(R, U, ca.DM.zeros(len(us))), 1)
    Rs = ca.vertsplit(R, 1)
    for k, b in enumerate(blocks):
        if nonlinear[k] or k not in diag:
            result[b] = ([us[k]], [labels[int(match[rows[k]])]], [Rs[k]])
            continue
        value = sol[k] / diag[k]
        if not diag[k].is_constant():      # a coefficient of parameters: a loop's 1 - k
            pivots.append((diag[k], [eqs[rows[k]][1]]))
        solved.append((us[k], value))
        known[us[k].name()] = value
