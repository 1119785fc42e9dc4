"""The straight-line C's versions for fixed parameter values
(native/specialise.py): each rule gives the value the operation gives in C,
but for the sign of a zero, at ordinary and special values (zeros of both
signs, infinities, NaN, subnormals); the version is run only where the
parameters hold their values, so a run off them (a sweep over an exponent)
is the general function's."""
import ctypes
import itertools
import math
import re
import subprocess

import casadi as ca
import numpy as np
import pytest

from pdbfs.models import paper_rig
from pdbfs.native import specialise, toolchain
from pdbfs.native.codegen import generate
from pdbfs.native.straight import BINARY, HELPERS, UNARY

SPECIAL = [0.0, -0.0, 1.0, -1.0, 0.5, -2.5, 3.0, 1e-310, -5e-324, 1e300, -1e300, 1e308,
           math.inf, -math.inf, math.nan]


def _compile(text, directory, name):
    src, lib = directory / f"{name}.c", directory / f"{name}.so"
    src.write_text(text)
    target = toolchain.host_target()
    r = subprocess.run([*toolchain.compiler(target), *toolchain.cflags(target), "-shared",
                        "-fvisibility=default", str(src), "-o", str(lib), "-lm"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    return ctypes.CDLL(str(lib))


def _same(a, b):
    """Equal (a zero's sign aside), or both NaN."""
    return a == b or (math.isnan(a) and math.isnan(b))


def test_constants_fold_to_what_c_computes(tmp_path):
    """fold(op, a, b) is C's own value of the operation, spelled as the
    straight-line C spells it, for every operation it folds and every pair
    of special values; it declines (None) only fmax and fmin of two zeros
    of opposite signs (which zero is the library's)."""
    ops = [(op, UNARY[op]) for op in specialise.FOLD_UNARY] + \
        [(op, BINARY[op]) for op in specialise.FOLD_BINARY]
    cases = "\n".join(f"    case {k}: return {tmpl.format('a', 'b')};" for k, (_, tmpl) in
                      enumerate(ops))
    text = ("#include <math.h>\ntypedef double casadi_real;\n" + HELPERS % 1 +
            f"double op(int k, double a, double b) {{\n  switch (k) {{\n{cases}\n  }}\n"
            "  return NAN;\n}\n")
    lib = _compile(text, tmp_path, "ops")
    lib.op.restype = ctypes.c_double
    lib.op.argtypes = [ctypes.c_int, ctypes.c_double, ctypes.c_double]
    folded = declined = 0
    for k, (op, _) in enumerate(ops):
        unary = op in specialise.FOLD_UNARY
        for a, b in itertools.product(SPECIAL, [0.0] if unary else SPECIAL):
            want = lib.op(k, a, b)
            got = specialise.fold(op, a, None if unary else b)
            if got is None:
                declined += 1
                assert a == b == 0 and math.copysign(1, a) != math.copysign(1, b), (op, a, b)
                continue
            folded += 1
            assert _same(got, want) and (got != 0 or math.copysign(1, got) ==
                                         math.copysign(1, want)), (UNARY.get(op) or BINARY[op],
                                                                   a, b, got, want)
    assert folded > 2000 and declined > 0


def _rules_function():
    """A function of x through every rule, its parameters fixed at values each
    rule uses (0, 1, -1 and exponents)."""
    t, x, z = ca.SX.sym("t"), ca.SX.sym("x", 2), ca.SX.sym("z", 0)
    p = ca.SX.sym("p", 10)
    u, w = x[0], x[1]
    zero, one, mone = p[0], p[1], p[2]
    outs = [u + zero, zero + u, u - zero, zero - u, u * one, one * u, u * mone, u / one,
            u / mone, -(-(u + zero)), u ** p[3], u ** p[4], u ** p[5], u ** p[6], u ** p[7],
            u ** p[8], ca.fmax(u + zero, 0.0) ** p[3], ca.if_else(one > 0, u, w),
            ca.if_else(zero > 0, u, w), ca.logic_and(zero, u), ca.logic_or(one, u),
            (one == 1) * u + (zero < -1) * w, p[9] * u]
    f = ca.Function("pdbfs_rules", [t, x, z, p], [ca.vertcat(*outs)], ["t", "x", "z", "p"],
                    ["out"])
    values = {0: 0.0, 1: 1.0, 2: -1.0, 3: 1.5, 4: 1.0, 5: 2.0, 6: 0.0, 7: 3.0, 8: 0.5, 9: 7.25}
    return f, values


def test_every_rule_gives_the_operations_value(tmp_path):
    """The version made for the fixed values gives CasADi's C's numbers (its
    pow through pdbfs_pow) at those values, for x at every special value; a
    parameter a rule cannot use (7.25, a plain factor) is read, not fixed."""
    f, values = _rules_function()
    (tmp_path / "casadi").mkdir()
    (tmp_path / "own").mkdir()
    generate([f], tmp_path / "casadi", name="ref")
    generate([f], tmp_path / "own", name="own", straight=("pdbfs_rules",), values=values)
    text = (tmp_path / "own" / "own.c").read_text()
    guard = next(line for line in text.splitlines() if "return pdbfs_rules_fixed(" in line)
    assert "p[9]" not in guard and all(f"p[{k}]" in guard for k in range(9)), guard
    fixed = text.split("int pdbfs_rules_fixed(")[1].split("\n}\n")[0]
    assert "sqrt(" in fixed and not re.search(r"pdbfs_pow\([^,]+,i3\[", fixed)  # exponents in
    ref = _compile((tmp_path / "casadi" / "ref.c").read_text(), tmp_path, "ref")
    own = _compile(text, tmp_path, "own")
    p = np.array([values[k] for k in range(10)])
    n = f.nnz_out(0)
    compared = 0
    for a, b in itertools.product(SPECIAL, [2.0, -0.0, math.nan]):
        x = np.array([a, b])
        outs = []
        for lib in (ref, own):
            out = np.full(n, 12345.0)
            arg = (ctypes.c_void_p * 4)(None, x.ctypes.data, None, p.ctypes.data)
            res = (ctypes.c_void_p * 1)(out.ctypes.data)
            w = np.zeros(f.sz_w() + 1)
            iw = np.zeros(f.sz_iw() + 1, dtype=np.int64)
            assert lib.pdbfs_rules(arg, res, ctypes.c_void_p(iw.ctypes.data),
                                   ctypes.c_void_p(w.ctypes.data), 0) == 0
            outs.append(out)
        for k, (u, v) in enumerate(zip(*outs)):
            assert _same(u, v), (k, a, b, u, v)
            compared += 1
    assert compared == n * len(SPECIAL) * 3


def test_worth_fixing_takes_plain_values_and_exponents_only():
    f, values = _rules_function()
    got = specialise.worth_fixing(f, 3, values)
    assert set(got) == set(range(9)) and 9 not in got
    assert specialise.exponent_inputs(f, 3) == {3, 4, 5, 6, 7, 8}


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


def test_a_run_off_the_fixed_values_is_the_general_functions(rig):
    """An exponent other than the contact's default 1.5 (a sweep over
    contact.n) runs the general version: the compiled back end agrees with
    CasADi's at 1.45 as at 1.5, and the two peaks differ by what the law
    makes of them."""
    at = {}
    for n in (1.5, 1.45):
        c = rig.simulate(backend="c", params={"contact.n": n}).summary()["peak_pressure"]
        ref = rig.simulate(backend="casadi", params={"contact.n": n}).summary()["peak_pressure"]
        assert abs(c - ref) < 1e-6 * ref, (n, c, ref)
        at[n] = c
    assert abs(at[1.45] - at[1.5]) > 1e-3 * at[1.5]
