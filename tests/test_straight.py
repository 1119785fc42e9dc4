"""The compiled backend's inner-loop functions as straight-line C
(native/straight.py) give CasADi's own C's numbers to the bit: both are
compiled here from the same CasADi functions of every rig and called on the
same random points (contacts open and closed, an oil column slack and
squeezed, a friction coefficient zero and not), with the parameters at
their defaults (the versions made for them, specialise.py) and off them
(an exponent or a gap changed: the general versions)."""
import ctypes
import subprocess

import numpy as np
import pytest

from pdbfs.models import RIGS
from pdbfs.native import toolchain
from pdbfs.native.codegen import generate, model_functions, usual_values
from pdbfs.simulation import Simulator
from pdbfs.simulation.run.compiled_build import STRAIGHT, roles_of

WHICH = ("ode", "events", "roles", "roles_dot", "roles_both", "ode_q")


def _library(funcs, directory, straight, values=None):
    directory.mkdir()
    generate(funcs, directory, straight=straight, values=values)
    src = directory / "pdbfs_model_funcs.c"
    out = directory / "funcs.so"
    cmd = [*toolchain.compiler(), "-std=gnu99", "-O2", "-fno-math-errno", "-ffp-contract=off",
           "-fPIC", "-shared", str(src), "-o", str(out), "-lm"]
    subprocess.run(cmd, check=True, capture_output=True)
    return ctypes.CDLL(str(out)), src.read_text()


def _call(lib, f, args):
    fn = getattr(lib, f.name())
    fn.restype = ctypes.c_int
    ins = [np.ascontiguousarray(a, dtype=float) for a in args]
    outs = [np.full(f.nnz_out(i), np.nan) for i in range(f.n_out())]
    arg = (ctypes.c_void_p * max(f.sz_arg(), len(ins)))(*[a.ctypes.data for a in ins])
    res = (ctypes.c_void_p * max(f.sz_res(), 1))(*[o.ctypes.data for o in outs])
    iw = np.zeros(f.sz_iw() + 1, dtype=np.int64)
    w = np.zeros(f.sz_w() + 1)
    assert fn(arg, res, ctypes.c_void_p(iw.ctypes.data), ctypes.c_void_p(w.ctypes.data), 0) == 0
    return outs


@pytest.mark.parametrize("name", ["paper", "paper-hydraulic-oil", "hydraulic-pulse", "drop"])
def test_straight_c_is_casadis_c_to_the_bit(name, tmp_path):
    rig = RIGS[name]()
    sim = Simulator.of(rig)
    dae = sim.dae
    force = (getattr(dae, "signals", {}) or {}).get("contact_force")
    funcs = model_functions(dae, WHICH, roles=roles_of(dae),
                            quad=[force] if force in dae.y_names else [])
    ref, _ = _library(funcs, tmp_path / "casadi", ())
    values = usual_values(dae)
    own, text = _library(funcs, tmp_path / "straight", STRAIGHT, values)
    assert text.count("straight-line C (native/straight.py) */") >= 4, "nothing was straightened"
    assert "_fixed(arg, res, iw, w, mem)" in text, "nothing was specialised"
    rng = np.random.default_rng(7)
    p0 = sim.param_vector(None)
    fixed = sorted(values)
    x0 = sim.start_vector(p0, None)
    scale = np.maximum(np.abs(x0), 1e-3)
    compared = 0
    for trial in range(300):
        p = p0 * (1 + 0.2 * rng.uniform(-1, 1, p0.size)) if trial % 3 else p0.copy()
        if trial % 5 == 4:                      # a zero coefficient: its tanh skipped
            p[rng.integers(p.size)] = 0.0
        if trial % 7 == 6:                      # one fixed value changed: the general version
            k = fixed[rng.integers(len(fixed))]
            p = p0.copy()
            p[k] = p0[k] + 0.25 if p0[k] else 1e-3
        x = x0 + scale * rng.normal(size=x0.size) * 10.0 ** rng.integers(-6, 1)
        t = rng.uniform(0, 0.02)
        for f in funcs:
            nx = f.nnz_in(1)
            xx = np.r_[x, rng.normal(size=nx - x.size)] if nx > x.size else x
            third = rng.normal(size=f.nnz_in(2))      # z (empty) or roles_both's v
            args = [[t], xx, third, p]
            a, b = _call(ref, f, args), _call(own, f, args)
            for u, v in zip(a, b):
                same = (u == v) | (np.isnan(u) & np.isnan(v))
                assert same.all(), (name, f.name(), trial, u[~same], v[~same])
                compared += u.size
    assert compared > 1000
