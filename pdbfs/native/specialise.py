"""The rules by which straight.py simplifies a function for fixed parameter
values (a contact's exponent 1.5, a gap of 0, a linear spring's exponent
1): constant operations folded and identities dropped, each giving the
value the operation gives, but for the sign of a zero:

* an operation of constants only is computed now (IEEE double, as C would;
  only those C computes exactly: + - * /, comparisons, logic, negation,
  sqrt, fabs, floor, ceil; fmax and fmin but of two zeros);
* ``x + 0``, ``x - 0``, ``x * 1``, ``x / 1`` give ``x``; ``x * -1``,
  ``x / -1``, ``0 - x`` give ``-x``; ``-(-x)`` gives ``x``;
* ``c ? x : 0`` with c constant is ``x`` or 0; ``0 && x`` is 0, ``1 || x`` is 1;
* a power with a constant exponent: 1 gives ``x``, 0 gives 1, 2 gives
  ``x*x`` (as ``pdbfs_pow``, bit for bit); any other exponent is a
  ``pdbfs_pow`` call with the exponent written in, which the compiler
  reduces to its one case (1.5: ``x*sqrt(x)``, ``x*sqrt(x)`` itself where x
  is an ``fmax`` with a non-negative constant, never below zero).

A zero's sign is the one thing these may change (``x + 0`` is +0 for
x = -0): it changes no comparison, sum or product but one with an infinity,
and the rigs' functions divide by parameters only.
"""
from __future__ import annotations

import math

import casadi as ca

#: values of a parameter worth fixing beside a power's exponent: they let an
#: operation go (x + 0, x * 1, x * -1)
PLAIN = (0.0, 1.0, -1.0)


def _op(name: str) -> int:
    return getattr(ca, name, -1)


ADD, SUB, MUL, DIV, NEG = _op("OP_ADD"), _op("OP_SUB"), _op("OP_MUL"), _op("OP_DIV"), _op("OP_NEG")
POW, CONSTPOW, SQ, FMAX = _op("OP_POW"), _op("OP_CONSTPOW"), _op("OP_SQ"), _op("OP_FMAX")
IF_ELSE_ZERO, AND, OR = _op("OP_IF_ELSE_ZERO"), _op("OP_AND"), _op("OP_OR")
POWERS = (POW, CONSTPOW)


def _sign(x: float) -> float:
    return -1.0 if x < 0 else 1.0 if x > 0 else x


def _div(a: float, b: float) -> float:
    if b != 0 or math.isnan(b):
        return a / b if not math.isnan(b) else math.nan
    if a == 0 or math.isnan(a):
        return math.nan
    return math.copysign(math.inf, a) * math.copysign(1.0, b)


def _minmax(pick):
    def f(a, b):
        if math.isnan(a):
            return b
        if math.isnan(b):
            return a
        if a == b == 0 and math.copysign(1, a) != math.copysign(1, b):
            return None                       # which zero is the library's
        return pick(a, b)
    return f


def _sqrt(a: float) -> float:
    if math.isnan(a) or a < 0:
        return math.nan
    return a if a == 0 or math.isinf(a) else math.sqrt(a)


def _floor_ceil(f):
    def g(a):
        if math.isnan(a) or math.isinf(a) or a == 0:
            return a
        r = float(f(a))
        return math.copysign(r, a) if r == 0 else r      # ceil(-0.5) is -0
    return g


def _truth(a: float) -> bool:
    return a != 0                              # C: NaN is true


#: operations of constants C computes exactly, as Python computes them (None: not folded)
FOLD_UNARY = {_op(k): f for k, f in {
    "OP_ASSIGN": lambda a: a, "OP_NEG": lambda a: -a, "OP_SQ": lambda a: a * a,
    "OP_TWICE": lambda a: 2.0 * a, "OP_INV": lambda a: _div(1.0, a),
    "OP_NOT": lambda a: float(not _truth(a)), "OP_SQRT": _sqrt, "OP_FABS": abs,
    "OP_FLOOR": _floor_ceil(math.floor), "OP_CEIL": _floor_ceil(math.ceil), "OP_SIGN": _sign,
}.items() if hasattr(ca, k)}
FOLD_BINARY = {_op(k): f for k, f in {
    "OP_ADD": lambda a, b: a + b, "OP_SUB": lambda a, b: a - b, "OP_MUL": lambda a, b: a * b,
    "OP_DIV": _div, "OP_FMAX": _minmax(max), "OP_FMIN": _minmax(min),
    "OP_LT": lambda a, b: float(a < b), "OP_LE": lambda a, b: float(a <= b),
    "OP_EQ": lambda a, b: float(a == b), "OP_NE": lambda a, b: float(a != b),
    "OP_AND": lambda a, b: float(_truth(a) and _truth(b)),
    "OP_OR": lambda a, b: float(_truth(a) or _truth(b)),
    "OP_IF_ELSE_ZERO": lambda a, b: b if _truth(a) else 0.0,
}.items() if hasattr(ca, k)}


def _safe(f, *args):
    """f(*args) as IEEE doubles give it (an overflow is an infinity), or None."""
    try:
        return f(*args)
    except OverflowError:
        return None


def fold(op: int, a: float, b: float | None = None) -> float | None:
    """The constant an operation of constants gives (b None: unary), or None
    where C would not compute it exactly as Python does."""
    if b is None:
        f = FOLD_UNARY.get(op)
        return None if f is None else _safe(f, a)
    if op in POWERS:
        return {0.0: 1.0, 1.0: a, 2.0: a * a}.get(b)       # pdbfs_pow's exact cases
    f = FOLD_BINARY.get(op)
    return None if f is None else _safe(f, a, b)


def identity(op: int, a: str, b: str, ca_: float | None, cb: float | None):
    """A simpler form of ``a op b`` where one operand is a constant (ca_ of a,
    cb of b; None: not constant): ("same", value), ("const", number),
    ("op", op, operand) (a unary operation), ("pow", base, exponent), or None."""
    if op == ADD:
        if cb == 0:
            return ("same", a)
        if ca_ == 0:
            return ("same", b)
    elif op == SUB:
        if cb == 0:
            return ("same", a)
        if ca_ == 0:
            return ("op", NEG, b)
    elif op in (MUL, DIV):
        if cb == 1:
            return ("same", a)
        if cb == -1:
            return ("op", NEG, a)
        if op == MUL and ca_ == 1:
            return ("same", b)
        if op == MUL and ca_ == -1:
            return ("op", NEG, b)
    elif op in POWERS and cb is not None:
        if cb == 1:
            return ("same", a)
        if cb == 0:
            return ("const", 1.0)
        if cb == 2:
            return ("op", SQ, a)
        return ("pow", a, cb)
    elif op == IF_ELSE_ZERO and ca_ is not None:
        return ("same", b) if _truth(ca_) else ("const", 0.0)
    elif op == AND and (ca_ == 0 or cb == 0):
        return ("const", 0.0)
    elif op == OR and ((ca_ is not None and _truth(ca_)) or (cb is not None and _truth(cb))):
        return ("const", 1.0)
    return None


def never_negative(op: int, ca_: float | None, cb: float | None) -> bool:
    """Whether ``fmax`` with these operands is never below zero nor NaN."""
    return op == FMAX and any(c is not None and c >= 0 for c in (ca_, cb))


def exponent_inputs(f: ca.Function, p: int) -> set[int]:
    """The entries of input ``p`` of ``f`` that are the exponent of a power."""
    origin, found = {}, set()
    for k in range(f.n_instructions()):
        op, ins, outs = f.instruction_id(k), f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_OUTPUT:
            continue
        if op == ca.OP_INPUT:
            origin[outs[0]] = (ins[0], ins[1])
            continue
        if op in POWERS and origin.get(ins[1], (None,))[0] == p:
            found.add(origin[ins[1]][1])
        origin.pop(outs[0], None)
    return found


def worth_fixing(f: ca.Function, p: int, values: dict[int, float]) -> dict[int, float]:
    """Of ``values`` ({entry of input p: value}), those a rule can use in
    ``f``: PLAIN values, and exponents of powers."""
    exps = exponent_inputs(f, p)
    return {k: float(v) for k, v in values.items()
            if math.isfinite(v) and (float(v) in PLAIN or k in exps)}
