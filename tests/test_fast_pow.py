"""The generated C's pow (pdbfs.native.codegen.fast_pow, issue 23): a
contact law's exponent 1.5 (and 0, 0.5, 1, 2, 3) without libm's general pow,
the same value to an ulp (two for 3) and the same special cases as pow, everything
else passed to pow; compiled with the backend's own compiler."""
import ctypes
import math
import subprocess

import numpy as np
import pytest

from pdbfs.native import toolchain
from pdbfs.native.codegen import POW_HELPER, fast_pow


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    """(pdbfs_pow, libm's pow) from one library built as the backend builds."""
    tmp = tmp_path_factory.mktemp("pow")
    src = tmp / "p.c"
    src.write_text(fast_pow("#include <math.h>\n"
                            "double via_helper(double x, double y) { return pow(x, y); }\n")
                   + "double via_libm(double x, double y) { return (pow)(x, y); }\n")
    lib = tmp / "p.so"
    target = toolchain.host_target()
    r = subprocess.run([*toolchain.compiler(target), *toolchain.cflags(target), "-shared",
                        "-fvisibility=default", str(src), "-o", str(lib), "-lm"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-2000:]
    dll = ctypes.CDLL(str(lib))
    for f in (dll.via_helper, dll.via_libm):
        f.restype = ctypes.c_double
        f.argtypes = [ctypes.c_double, ctypes.c_double]
    return dll.via_helper, dll.via_libm


def test_every_pow_call_goes_through_the_helper_and_nothing_else_changes():
    c = "#include <math.h>\nstatic double f(double a) { return pow(a, 1.5) + my_pow(a) + x.pow(a); }\n"
    out = fast_pow(c)
    assert out.count("pdbfs_pow(a, 1.5)") == 1 and "my_pow(a)" in out and "x.pow(a)" in out
    assert out.startswith("#include <math.h>\n" + POW_HELPER)
    assert "static double pdbfs_pow(" in out           # internal: an FMU exports nothing more
    assert fast_pow("int f(void) { return 1; }\n") == "int f(void) { return 1; }\n"


SPECIAL = [0.0, -0.0, 1.0, -1.0, 2.0, 1e-310, 5e-324, 1e300, -1e300, math.inf, -math.inf, math.nan,
           0.25, 7.5, -2.5]


@pytest.mark.parametrize("y", [1.5, 0.5, 1.0, 2.0, 3.0, 2.5, -1.5, 0.0])
def test_special_values_as_pow(both, y):
    helper, libm = both
    for x in SPECIAL:
        got, want = helper(x, y), libm(x, y)
        if math.isnan(want):
            assert math.isnan(got), (x, y, got)
        else:
            assert got == want and math.copysign(1, got) == math.copysign(1, want), (x, y, got, want)


@pytest.mark.parametrize("y", [1.5, 0.5, 1.0, 2.0, 0.0])
def test_within_an_ulp_of_pow(both, y):
    helper, libm = both
    rng = np.random.default_rng(3)
    xs = np.concatenate([10.0 ** rng.uniform(-300, 200, 2000), rng.uniform(0, 1e-2, 2000)])
    for x in xs:
        got, want = helper(float(x), y), libm(float(x), y)
        assert got == want or abs(got - want) <= math.ulp(want), (x, y, got, want)


def test_a_cube_within_two_ulp_of_pow(both):
    """x^3 as x*x*x: two roundings, both signs, wherever the cube is a normal number"""
    helper, libm = both
    rng = np.random.default_rng(4)
    xs = 10.0 ** rng.uniform(-100, 100, 4000) * rng.choice([-1.0, 1.0], 4000)
    worst = 0.0
    for x in xs:
        got, want = helper(float(x), 3.0), libm(float(x), 3.0)
        worst = max(worst, abs(got - want) / math.ulp(want))
    assert worst <= 2.0, worst
