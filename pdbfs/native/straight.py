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

from . import specialise
from .specialise import NEG

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


def _body(f: ca.Function, fixed: dict):
    """(lines, outputs, inputs read, fixed entries a rule used, fixed entries
    read) of ``f``'s straight-line body, the entries of ``fixed`` ({(input,
    entry): value}) taken as those constants and simplified by the rules of
    specialise.py; None for an operation not in UNARY or BINARY."""
    slot = {}          # CasADi's work slot -> the value it holds now
    seen = {}          # an operation and its operands -> its value (common subexpressions)
    lines, outputs, reads = [], [], set()
    bounded = {}       # value of a bounded function -> (its line, its operation, its argument)
    const = {}         # value -> (the constant it is, the fixed entries it comes from)
    nonneg = set()     # values never below zero nor NaN (specialise.never_negative)
    neg_of = {}        # value -> the value it is the negation of
    used, fixed_read = set(), set()
    for k in range(f.n_instructions()):
        op = f.instruction_id(k)
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        if op == ca.OP_OUTPUT:
            outputs.append((outs[0], outs[1], slot[ins[0]]))
            continue
        rule, src = None, frozenset()
        if op == ca.OP_INPUT and (ins[0], ins[1]) in fixed:
            v = float(fixed[ins[0], ins[1]])
            key, text, src = ("c", v.hex()), _literal(v), {(ins[0], ins[1])}
            fixed_read.add((ins[0], ins[1]))
        elif op == ca.OP_INPUT:
            key, text = ("in", ins[0], ins[1]), f"i{ins[0]}[{ins[1]}]"
            reads.add(ins[0])
        elif op == ca.OP_CONST:
            v = float(f.instruction_constant(k))
            key, text = ("c", v.hex()), _literal(v)
        elif op in UNARY or op in BINARY:
            a = slot[ins[0]]
            b = slot[ins[1]] if op in BINARY else None
            if fixed:
                rule, src = _simplified(op, a, b, const, neg_of)
            if rule is not None and rule[0] == "same":
                used.update(src)
                slot[outs[0]] = rule[1]
                continue
            if rule is not None and rule[0] == "const":
                v = rule[1]
                key, text = ("c", v.hex()), _literal(v)
            elif rule is not None and rule[0] == "op":
                op, a, b = rule[1], rule[2], None
                key, text = (op, a), UNARY[op].format(a)
            elif rule is not None:                      # a power with its exponent written in
                base, y = rule[1], rule[2]
                key = ("pow", base, y.hex())
                text = f"({base}*sqrt({base}))" if y == 1.5 and base in nonneg else \
                    f"pdbfs_pow({base},{_literal(y)})"
            elif b is None:
                key, text = (op, a), UNARY[op].format(a)
            else:
                if op in COMMUTATIVE and b < a:
                    a, b = b, a
                key, text = (op, a, b), BINARY[op].format(a, b)
        else:
            return None
        if rule is not None:
            used.update(src)
        value = seen.get(key)
        if value is None:
            if key[0] == "c" or key[0] == "in":
                value = text                   # read where used: no variable of its own
                if key[0] == "c":
                    const[value] = (float.fromhex(key[1]), frozenset(src))
            else:
                value = f"v{len(lines)}"
                if op in BOUNDED and key[0] == op:
                    bounded[value] = (len(lines), op, key[1])
                if key[0] == op == NEG:
                    neg_of[value] = key[1]
                if b is not None and specialise.never_negative(op, const.get(a, (None,))[0],
                                                               const.get(b, (None,))[0]):
                    nonneg.add(value)
                lines.append(f"  const casadi_real {value} = {text};")
            seen[key] = value
        elif key[0] == "c":                     # the same constant from other fixed entries too
            c, s0 = const[value]
            const[value] = (c, s0 | frozenset(src))
        slot[outs[0]] = value
    _zero_factors(lines, outputs, bounded)
    return lines, outputs, reads, used, fixed_read


def _simplified(op, a, b, const, neg_of):
    """(specialise's simpler form of ``op`` on values a, b (None: unary), the
    fixed entries the constants it used come from)."""
    ca_, sa = const.get(a, (None, frozenset()))
    cb, sb = const.get(b, (None, frozenset())) if b is not None else (None, frozenset())
    if op == NEG and a in neg_of:
        return ("same", neg_of[a]), frozenset()
    if ca_ is not None and (b is None or cb is not None):
        v = specialise.fold(op, ca_, cb)
        return (None if v is None else ("const", v)), sa | sb
    if b is None:
        return None, frozenset()
    rule = specialise.identity(op, a, b, ca_, cb)
    return rule, (sa if ca_ is not None else frozenset()) | (sb if cb is not None else frozenset())


def _function(f, name, body, storage="") -> str:
    lines, outputs, reads = body[:3]
    head = [f"/* {f.name()}: straight-line C (native/straight.py) */",
            f"{storage}int {name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, "
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


def straight_c(f: ca.Function, name: str, values: dict[int, float] | None = None) -> str | None:
    """The C function ``name`` (CasADi's signature) computing ``f``, or None
    when ``f`` is not an SX function, too large, or uses an operation not
    in UNARY or BINARY. ``values``: entries of the input named ``p`` that
    are usually these values ({entry: value}, the parameters' defaults);
    where fixing some simplifies ``f`` (specialise.py), the function tests
    them at every call and runs a version made for them when all hold."""
    if not f.is_a("SXFunction") or f.n_instructions() > PART_INSTRUCTIONS:
        return None
    body = _body(f, {})
    if body is None:
        return None
    counts = [0] * f.n_out()
    for o, _, _ in body[1]:
        counts[o] += 1
    if any(c != f.nnz_out(o) for o, c in enumerate(counts)):
        return None                            # an output not written whole: leave it to CasADi
    p = f.name_in().index("p") if values and "p" in f.name_in() else None
    fixed = {(p, k): v for k, v in specialise.worth_fixing(f, p, values).items()} \
        if p is not None else {}
    if fixed:
        first = _body(f, fixed)
        fixed = {e: fixed[e] for e in first[3]}          # only those a rule used
    special = _body(f, fixed) if fixed else None
    if special is None or not special[4]:
        return _function(f, name, body)
    guard = " && ".join(f"p[{k}] == {_literal(fixed[i, k])}" for i, k in sorted(special[4]))
    return "\n".join([
        _function(f, f"{name}_any", body, "static "),
        _function(f, f"{name}_fixed", special, "static "),
        f"/* {f.name()}: its version for the parameters p (pdbfs_for_params: for_params) */",
        f"static pdbfs_model_fn {name}{FOR}(const casadi_real *p) {{",
        f"  return p && {guard} ? {name}_fixed : {name}_any;", "}",
        f"/* {f.name()}: the version for the usual values of its parameters where they hold */",
        f"int {name}(const casadi_real** arg, casadi_real** res, casadi_int* iw, casadi_real* w, "
        "int mem) {",
        f"  const casadi_real *p = arg[{p}];",
        f"  if (p && {guard}) return {name}_fixed(arg, res, iw, w, mem);",
        f"  return {name}_any(arg, res, iw, w, mem);", "}", ""])


#: the suffix of a straight function's choice of its version (straight_c, for_params)
FOR = "_for"
#: the model functions' type, for that choice (in the generated C before the straight functions)
MODEL_FN = ("typedef int (*pdbfs_model_fn)(const casadi_real**, casadi_real**, casadi_int*, "
            "casadi_real*, int);\n")


def for_params(own: dict[str, str]) -> str:
    """The C function ``pdbfs_for_params(f, p)`` (declared in pdbfs_cvode.h):
    the version of model function ``f`` made for the parameters ``p``, the
    ``_fixed`` or ``_any`` one of a straight function of ``own`` ({name:
    straight_c's text}) made in two, else ``f`` itself. The same numbers as
    ``f`` called with ``p``, without the test of p's usual values at every
    call: a driver asks once per run (p does not change within one).

    Parameters
    ----------
    own : dict of str to str
        The straight-line functions of the generated C, by name.

    Returns
    -------
    str
        The function's C text (after ``own``'s)."""
    picks = [f"  if (f == {n}) return {n}{FOR}(p);" for n, text in own.items()
             if f"pdbfs_model_fn {n}{FOR}(" in text]
    return "\n".join([
        "/* pdbfs (native/straight.py): a model function's version for the parameters p */",
        "pdbfs_model_fn pdbfs_for_params(pdbfs_model_fn f, const casadi_real *p);",
        "pdbfs_model_fn pdbfs_for_params(pdbfs_model_fn f, const casadi_real *p) {",
        *picks, "  (void)p;", "  return f;", "}", ""])


def zeros_needed(funcs) -> int:
    """Entries of pdbfs_zeros (HELPERS): the largest input of ``funcs``."""
    return max([1] + [f.nnz_in(i) for f in funcs for i in range(f.n_in())])
