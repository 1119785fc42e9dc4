"""Evaluate a CasADi SXFunction on many points at once with numpy.

CasADi's ``map`` calls the function once per point, with a fixed overhead
per call that dominates for the small output functions of a rig (about
1 us a point here). Replaying the function's instruction list on whole numpy
rows costs one numpy operation per instruction instead. Functions using an
operation not listed here fall back to ``map`` (``vectorize`` returns None).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

_f = lambda fn: (lambda *a: fn(*a).astype(float))   # comparisons give 0.0 / 1.0

UNARY = {
    ca.OP_NEG: np.negative, ca.OP_SQ: np.square, ca.OP_SQRT: np.sqrt, ca.OP_EXP: np.exp,
    ca.OP_LOG: np.log, ca.OP_SIN: np.sin, ca.OP_COS: np.cos, ca.OP_TAN: np.tan,
    ca.OP_ASIN: np.arcsin, ca.OP_ACOS: np.arccos, ca.OP_ATAN: np.arctan,
    ca.OP_SINH: np.sinh, ca.OP_COSH: np.cosh, ca.OP_TANH: np.tanh, ca.OP_FABS: np.abs,
    ca.OP_SIGN: np.sign, ca.OP_FLOOR: np.floor, ca.OP_CEIL: np.ceil,
    ca.OP_TWICE: lambda a: 2.0 * a, ca.OP_INV: lambda a: 1.0 / a,
    ca.OP_NOT: _f(np.logical_not), ca.OP_ASSIGN: lambda a: a,
}
BINARY = {
    ca.OP_ADD: np.add, ca.OP_SUB: np.subtract, ca.OP_MUL: np.multiply, ca.OP_DIV: np.divide,
    ca.OP_POW: np.power, ca.OP_CONSTPOW: np.power, ca.OP_FMAX: np.fmax, ca.OP_FMIN: np.fmin,
    ca.OP_ATAN2: np.arctan2, ca.OP_FMOD: np.fmod, ca.OP_COPYSIGN: np.copysign,
    ca.OP_HYPOT: np.hypot,
    ca.OP_LT: _f(np.less), ca.OP_LE: _f(np.less_equal), ca.OP_EQ: _f(np.equal),
    ca.OP_NE: _f(np.not_equal), ca.OP_AND: _f(np.logical_and), ca.OP_OR: _f(np.logical_or),
    ca.OP_IF_ELSE_ZERO: lambda c, x: np.where(c != 0, x, 0.0),
}


def vectorize(f: ca.Function):
    """A function of numpy arrays (one row per input entry, one column per
    point, or a single column to broadcast) returning one (n_out, N) array
    per output (a row per entry, structural zeros included), or None if
    ``f`` uses an operation not supported here."""
    if not f.is_a("SXFunction"):
        return None
    program = []
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_INPUT:
            program.append(("in", outs[0], ins[0], ins[1]))
        elif op == ca.OP_OUTPUT:
            program.append(("out", ins[0], outs[0], outs[1]))     # (output, its nonzero)
        elif op == ca.OP_CONST:
            program.append(("const", outs[0], f.instruction_constant(k)))
        elif op in UNARY:
            program.append(("f1", outs[0], UNARY[op], ins[0]))
        elif op in BINARY:
            program.append(("f2", outs[0], BINARY[op], ins[0], ins[1]))
        else:
            return None
    # an output's rows are its dense entries: a structural zero (the rate of a
    # constant) is a row of zeros, not left out (the rows after it would move up)
    sizes = [f.numel_out(i) for i in range(f.n_out())]
    where = [f.sparsity_out(i).find() for i in range(f.n_out())]

    def run(*args):
        args = [np.atleast_2d(np.asarray(a, dtype=float)) for a in args]
        n = max(a.shape[1] for a in args)
        w = [None] * f.sz_w()
        res = [np.zeros((s, n)) for s in sizes]
        with np.errstate(all="ignore"):
            for ins in program:
                kind = ins[0]
                if kind == "f2":
                    w[ins[1]] = ins[2](w[ins[3]], w[ins[4]])
                elif kind == "f1":
                    w[ins[1]] = ins[2](w[ins[3]])
                elif kind == "in":
                    w[ins[1]] = args[ins[2]][ins[3]]
                elif kind == "const":
                    w[ins[1]] = ins[2]
                else:
                    res[ins[2]][where[ins[2]][ins[3]]] = w[ins[1]]
        return res

    return run
