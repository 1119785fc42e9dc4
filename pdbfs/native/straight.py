"""Straight-line C for the model functions a compiled run calls thousands of
times (the right-hand side, the event indicators, the summary's roles):
written from the CasADi function's own instruction list, with

* each input read once through a local pointer, each output written at the
  end (CasADi's C tests every input pointer for NULL at every read, and
  reloads it after every store, since an output may alias it);
* common subexpressions computed once, commuted operands included (a
  contact and its damper each write ``-(s + gap)``, as ``-(gap + s)``,
  and each raised it to the power n: one square root instead of two).

The operations are CasADi's own, spelled as its C spells them (``fmax``,
``x*x`` for ``sq``, ``pdbfs_pow`` for powers as codegen.fast_pow makes
them), so the numbers are CasADi's to the bit; the calling convention is
CasADi's (``arg``, ``res``, ``iw``, ``w``, ``mem``; a NULL input reads as
zeros, a NULL output is not written), so the drivers call either.
A function with an operation not listed here, or too large (codegen.split
keeps those in parts), is left to CasADi (``straight_c`` returns None).
"""
from __future__ import annotations

import math
import re

import casadi as ca

#: instructions per generated C function at most, here and in codegen.split
#: (about 35 kB of C): GCC's optimisation grows faster than linearly with the
#: size of one function (measured on the split piston, N = 200: one function
#: per output, 17 s and 520 MB at -O2; in parts of 2,000 instructions, 5.7 s
#: and 295 MB; N = 1,000: 30 s and 760 MB)
PART_INSTRUCTIONS = 2000


def _ops(table):
    """{op code: C template} for the op names CasADi has (older ones lack some)."""
    return {getattr(ca, name): c for name, c in table.items() if hasattr(ca, name)}


UNARY = _ops({
    "OP_ASSIGN": "{0}", "OP_NEG": "(-{0})", "OP_SQ": "({0}*{0})", "OP_TWICE": "(2.*{0})",
    "OP_INV": "(1./{0})", "OP_NOT": "(!{0})", "OP_SQRT": "sqrt({0})", "OP_EXP": "exp({0})",
    "OP_LOG": "log({0})", "OP_SIN": "sin({0})", "OP_COS": "cos({0})", "OP_TAN": "tan({0})",
    "OP_ASIN": "asin({0})", "OP_ACOS": "acos({0})", "OP_ATAN": "atan({0})",
    "OP_SINH": "sinh({0})", "OP_COSH": "cosh({0})", "OP_TANH": "tanh({0})",
    "OP_ASINH": "asinh({0})", "OP_ACOSH": "acosh({0})", "OP_ATANH": "atanh({0})",
    "OP_FABS": "fabs({0})", "OP_SIGN": "pdbfs_sign({0})", "OP_FLOOR": "floor({0})",
    "OP_CEIL": "ceil({0})", "OP_ERF": "erf({0})", "OP_EXPM1": "expm1({0})",
    "OP_LOG1P": "log1p({0})",
})
BINARY = _ops({
    "OP_ADD": "({0}+{1})", "OP_SUB": "({0}-{1})", "OP_MUL": "({0}*{1})", "OP_DIV": "({0}/{1})",
    "OP_POW": "pdbfs_pow({0},{1})", "OP_CONSTPOW": "pdbfs_pow({0},{1})",
    "OP_FMAX": "fmax({0},{1})", "OP_FMIN": "fmin({0},{1})", "OP_ATAN2": "atan2({0},{1})",
    "OP_FMOD": "fmod({0},{1})", "OP_REMAINDER": "remainder({0},{1})",
    "OP_COPYSIGN": "copysign({0},{1})", "OP_HYPOT": "hypot({0},{1})",
    "OP_LT": "({0}<{1})", "OP_LE": "({0}<={1})", "OP_EQ": "({0}=={1})", "OP_NE": "({0}!={1})",
    "OP_AND": "({0}&&{1})", "OP_OR": "({0}||{1})", "OP_IF_ELSE_ZERO": "({0}?{1}:0)",
})
#: operations whose operands may be swapped: the same value either way (fmax and
#: fmin are not among them: which zero they give of -0 and +0 is the library's)
COMMUTATIVE = {getattr(ca, n) for n in ("OP_ADD", "OP_MUL", "OP_EQ", "OP_NE", "OP_AND", "OP_OR")
               if hasattr(ca, n)}

#: what the straight functions need beside <math.h> and pdbfs_pow (codegen.POW_HELPER)
HELPERS = """
/* pdbfs (native/straight.py): the helpers of the straight-line functions */
static const casadi_real pdbfs_zeros[%d] = {0};
static inline casadi_real pdbfs_sign(casadi_real x) { return x < 0 ? -1. : x > 0 ? 1. : x; }
"""


def _literal(v: float) -> str:
    if math.isnan(v):
        return "NAN"
    if math.isinf(v):
        return "INFINITY" if v > 0 else "(-INFINITY)"
    return f"({v!r})" if math.copysign(1.0, v) < 0 else repr(v)


#: functions finite wherever their argument is not NaN (sin and cos: finite)
BOUNDED = {getattr(ca, n) for n in ("OP_TANH", "OP_SIN", "OP_COS", "OP_ATAN", "OP_ERF")
           if hasattr(ca, n)}
PERIODIC = {ca.OP_SIN, ca.OP_COS}


def _zero_factors(lines, outputs, bounded):
    """Rewrite ``vJ = (a*vK)`` where vK is a bounded function of u (tanh,
    sin, ...) used by that product alone: the function is computed only where
    the other factor is not zero (a friction law's tanh with no Coulomb force
    cost as much as the rest of a rig's right-hand side). The same value, NaN
    where the function is NaN, but for the sign of a zero."""
    used = [v for _, _, v in outputs]
    for fn, (at, op, u) in bounded.items():
        word = re.compile(rf"\b{fn}\b")
        users = [i for i, line in enumerate(lines) if i != at and word.search(line)]
        if len(users) != 1 or fn in used:
            continue
        m = re.fullmatch(rf"  const casadi_real (v\d+) = \((?:{fn}\*(.+)|(.+)\*{fn})\);",
                         lines[users[0]])
        if not m:
            continue
        fac, call = m.group(2) or m.group(3), UNARY[op].format(u)
        # NaN where the function is: at a NaN, and for sin and cos at infinities
        nan = f"({u}-{u})" if op in PERIODIC else f"({u} == {u} ? 0.0 : {u})"
        lines[at] = f"  /* {fn} = {call}: below, where its factor is not zero */"
        lines[users[0]] = (f"  const casadi_real {m.group(1)} = "
                           f"({fac} != 0 ? {fac}*{call} : {fac}*{nan});")


def straight_c(f: ca.Function, name: str) -> str | None:
    """The C function ``name`` (CasADi's signature) computing ``f``, or None
    when ``f`` is not an SX function, too large, or uses an operation not
    in UNARY or BINARY."""
    if not f.is_a("SXFunction") or f.n_instructions() > PART_INSTRUCTIONS:
        return None
    slot = {}          # CasADi's work slot -> the value it holds now
    seen = {}          # an operation and its operands -> its value (common subexpressions)
    lines, outputs, reads = [], [], set()
    bounded = {}       # value of a bounded function -> (its line, its operation, its argument)
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_OUTPUT:
            outputs.append((outs[0], outs[1], slot[ins[0]]))
            continue
        if op == ca.OP_INPUT:
            key, text = ("in", ins[0], ins[1]), f"i{ins[0]}[{ins[1]}]"
            reads.add(ins[0])
        elif op == ca.OP_CONST:
            v = float(f.instruction_constant(k))
            key, text = ("c", v.hex()), _literal(v)
        elif op in UNARY:
            a = slot[ins[0]]
            key, text = (op, a), UNARY[op].format(a)
        elif op in BINARY:
            a, b = slot[ins[0]], slot[ins[1]]
            if op in COMMUTATIVE and b < a:
                a, b = b, a
            key, text = (op, a, b), BINARY[op].format(a, b)
        else:
            return None
        value = seen.get(key)
        if value is None:
            if key[0] == "c" or key[0] == "in":
                value = text                   # read where used: no variable of its own
            else:
                value = f"v{len(lines)}"
                if op in BOUNDED:
                    bounded[value] = (len(lines), op, key[1])
                lines.append(f"  const casadi_real {value} = {text};")
            seen[key] = value
        slot[outs[0]] = value
    _zero_factors(lines, outputs, bounded)
    counts = [0] * f.n_out()
    for o, _, _ in outputs:
        counts[o] += 1
    if any(c != f.nnz_out(o) for o, c in enumerate(counts)):
        return None                            # an output not written whole: leave it to CasADi
    head = [f"/* {f.name()}: straight-line C (native/straight.py) */",
            f"int {name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, "
            "casadi_real* w, int mem) {"]
    head += [f"  const casadi_real *i{i} = arg[{i}] ? arg[{i}] : pdbfs_zeros;"
             for i in sorted(reads)]
    tail = []
    for o in range(f.n_out()):
        tail.append(f"  if (res[{o}]) {{")
        tail += [f"    res[{o}][{nz}] = {v};" for oo, nz, v in outputs if oo == o]
        tail.append("  }")
    tail += ["  (void)iw; (void)w; (void)mem;", "  return 0;", "}", ""]
    return "\n".join(head + lines + tail)


def zeros_needed(funcs) -> int:
    """Entries of pdbfs_zeros (HELPERS): the largest input of ``funcs``."""
    return max([1] + [f.nnz_in(i) for f in funcs for i in range(f.n_in())])
