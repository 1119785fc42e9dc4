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


def test_the_version_for_the_parameters_is_the_functions_own_numbers(tmp_path):
    """pdbfs_for_params(f, p), the version the explicit method calls for a
    run's parameters (chosen once per start, not at every call), gives f's
    own numbers with p (CasADi's C, to the bit), a version of its own where p
    holds the usual values and another where it does not; f itself for a
    function without versions."""
    sim = Simulator.of(RIGS["paper"]())
    dae = sim.dae
    force = (getattr(dae, "signals", {}) or {}).get("contact_force")
    funcs = model_functions(dae, WHICH + ("events_both",), roles=roles_of(dae),
                            quad=[force] if force in dae.y_names else [])
    ref, _ = _library(funcs, tmp_path / "casadi", ())
    values = usual_values(dae)
    own, _ = _library(funcs, tmp_path / "straight", STRAIGHT, values)
    pick = own.pdbfs_for_params
    pick.restype = ctypes.c_void_p
    pick.argtypes = [ctypes.c_void_p, ctypes.c_void_p]
    sig = ctypes.CFUNCTYPE(ctypes.c_int, *[ctypes.c_void_p] * 4, ctypes.c_int)
    p0 = sim.param_vector(None)
    off = p0.copy()
    for k in values:                                      # every usual value changed
        off[k] = p0[k] + 0.25 if p0[k] else 1e-3
    x = sim.start_vector(p0, None) + 1e-4
    versions = 0
    for f in funcs:
        address = ctypes.cast(getattr(own, f.name()), ctypes.c_void_p).value
        chosen = {}
        for name, p in (("usual", p0), ("off", off)):
            chosen[name] = pick(address, p.ctypes.data)
            fn = sig(chosen[name])
            nx = f.nnz_in(1)
            xx = np.r_[x, np.full(nx - x.size, 0.5)] if nx > x.size else x
            args = [np.array([1e-3]), xx, np.linspace(-1, 1, f.nnz_in(2)), p]
            ins = [np.ascontiguousarray(a, dtype=float) for a in args]
            outs = [np.full(f.nnz_out(i), np.nan) for i in range(f.n_out())]
            arg = (ctypes.c_void_p * max(f.sz_arg(), 4))(*[a.ctypes.data for a in ins])
            res = (ctypes.c_void_p * max(f.sz_res(), 1))(*[o.ctypes.data for o in outs])
            iw, w = np.zeros(f.sz_iw() + 1, dtype=np.int64), np.zeros(f.sz_w() + 1)
            assert fn(ctypes.cast(arg, ctypes.c_void_p), ctypes.cast(res, ctypes.c_void_p),
                      iw.ctypes.data, w.ctypes.data, 0) == 0
            for u, v in zip(_call(ref, f, args), outs):
                assert ((u == v) | (np.isnan(u) & np.isnan(v))).all(), (f.name(), name, u, v)
        if f.name() == "pdbfs_events_both":                  # CasADi's: no versions
            assert chosen["usual"] == chosen["off"] == address
        elif chosen["usual"] != chosen["off"]:
            versions += 1
    assert versions >= 4, "no function chose a version of its own for the usual values"
