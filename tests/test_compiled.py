"""The compiled backend, ``simulate(..., backend="c")``: CVODE in a shared
library built from the DAE's generated C (pdbfs.simulation.run.compiled,
pdbfs/native/c/library/pdbfs_batch.c), against the CasADi path."""
import ctypes
import json

import numpy as np
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.components import Force, Mass
from pdbfs.errors import ParameterError, SolverError
from pdbfs.simulation.run import compiled as batch
from pdbfs.simulation.run import compiled_build as build
from pdbfs.models import paper_rig, split_piston_rig
from pdbfs.simulation import Simulator

from test_core import Chain

T = np.linspace(0.0, 0.02, 2001)


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.fixture(scope="module")
def split3():
    return split_piston_rig(3)


def _pressure_gap(rig, **kw):
    a = rig.simulate(t_out=T, backend="casadi", **kw)
    b = rig.simulate(t_out=T, backend="c", **kw)
    pa, pb = a["oil.pressure"], b["oil.pressure"]
    return np.max(np.abs(pa - pb)) / pa.max(), a, b


@pytest.mark.parametrize("over", [{}, {"hammer.v0": 4.23}, {"seal.c": 2.556e6}])
def test_agrees_with_the_casadi_path(rig, over):
    gap, a, b = _pressure_gap(rig, params=over)    # default tolerances: rtol 1e-8
    assert gap < 1e-6
    # as tests/test_accuracy.py: the breech's small fast motion is looser for both paths
    for k, name in enumerate(rig.compile().x_names):
        scale = np.max(np.abs(a._X[k]))
        tol = 1e-4 if name.startswith("breech") else 1e-5
        assert np.max(np.abs(a._X[k] - b._X[k])) < tol * scale, name
    assert b.settings["backend"] == "c" and b._Z.shape == (0, T.size)


def test_bdf_and_split_piston_agree(rig, split3):
    gap, _, _ = _pressure_gap(rig, method="bdf")
    assert gap < 1e-6
    gap, _, _ = _pressure_gap(split3)
    assert gap < 1e-6


def test_result_methods_and_summary_agree(rig):
    a = rig.simulate(n_out=201, backend="casadi")
    b = rig.simulate(n_out=201, backend="c", method="adams")    # the same method on both
    sa, sb = a.summary(), b.summary()
    for key in ("peak_pressure", "peak_contact_force", "max_piston_displacement",
                "restitution_coefficient"):
        assert sb[key] == pytest.approx(sa[key], rel=1e-6), key
    for key in ("time_of_peak", "pulse_duration"):
        assert sb[key] == pytest.approx(sa[key], abs=1e-9), key
    assert b.crossings("contact.d", 0.0)[0] == pytest.approx(a.crossings("contact.d", 0.0)[0],
                                                              abs=1e-10)
    assert b.value_at("oil.pressure", 5.55e-3) == pytest.approx(
        a.value_at("oil.pressure", 5.55e-3), rel=1e-6)


def test_results_do_not_depend_on_the_output_grid(rig):
    fine = rig.simulate(n_out=2001, backend="c")
    coarse = rig.simulate(n_out=21, backend="c")
    rng = np.random.default_rng(1)
    odd = np.unique(np.r_[0.0, rng.uniform(0.0, 0.02, 300), 0.02])
    ragged = rig.simulate(t_out=odd, backend="c")
    idx = np.searchsorted(fine.t, coarse.t)
    # the same CVODE steps whatever the grid: equal to round-off
    scale = np.max(np.abs(fine._X), axis=1, keepdims=True)
    assert np.max(np.abs(fine._X[:, idx] - coarse._X) / scale) < 1e-12
    assert np.max(np.abs(ragged._X[:, -1] - fine._X[:, -1]) / scale[:, 0]) < 1e-12
    # the peak is refined by integrating from the nearest output point: to the tolerance
    assert rig.simulate(n_out=101, backend="c").summary()["peak_pressure"] == pytest.approx(
        fine.summary()["peak_pressure"], rel=1e-8)


def test_dae_rig_is_refused_clearly():
    rig = Chain(2)      # two nonlinear springs in series: the node stays algebraic
    assert not rig.compile().is_ode
    with pytest.raises(ParameterError, match=r"backend='c' integrates ODE rigs only.*algebraic"
                                             r".*backend='casadi'"):
        rig.simulate(0.5, backend="c")
    rig.simulate(0.5, n_out=11)    # the CasADi path (IDAS) still works


def test_bad_settings_are_refused(rig):
    with pytest.raises(ParameterError, match="unknown backend 'fortran'"):
        rig.simulate(backend="fortran")
    with pytest.raises(ParameterError, match="max_num_steps"):
        rig.simulate(backend="c", max_num_steps=0)
    with pytest.raises(ParameterError, match="rtol"):
        rig.simulate(backend="c", rtol=float("nan"))
    with pytest.raises(ParameterError, match="hammer.v0"):
        rig.simulate(backend="c", params={"hammer.v0": float("inf")})


def test_the_library_checks_its_input(rig):
    c = Simulator.of(rig).compiled()
    p = Simulator.of(rig).param_vector()
    x0 = Simulator.of(rig).start_vector(p)
    X, st = c.run([0.0, 0.01, 0.005], x0, p, 1e-8, 1e-10)      # not increasing
    assert st.code == batch.RC_BAD_INPUT and "strictly increasing" in st.message
    X, st = c.run([0.0, 0.01], x0, p, -1.0, 1e-10)
    assert st.code == batch.RC_BAD_INPUT and "rtol" in st.message
    # wrong sizes straight into C (one state more is the contact force's impulse,
    # compiled.run's): refused, nothing written
    info = np.zeros(batch.INFO_N)
    msg = ctypes.create_string_buffer(256)
    t = np.array([0.0, 0.01])
    out = np.zeros(2 * c.nx)
    code = c._run(c.nx + c.nq + 1, c.np, p.ctypes.data, x0.ctypes.data, 2, t.ctypes.data,
                  out.ctypes.data, 1e-8, 1e-10, 0, 0.0, 100, info.ctypes.data, msg, 256)
    assert code == batch.RC_BAD_INPUT and b"sizes" in msg.value and not out.any()


def test_parameters_change_without_rebuilding(tmp_path, monkeypatch):
    # a fresh cache directory: exactly one build, then none
    monkeypatch.setattr(build, "cache_dir", lambda: tmp_path)
    before = build.BUILDS
    first = paper_rig()
    peaks = [first.simulate(backend="c", params={"hammer.v0": v})["oil.pressure"].max()
             for v in (1.87, 2.73, 4.23)]
    assert build.BUILDS == before + 1
    assert np.all(np.diff(peaks) > 0)
    lib = Simulator.of(first).compiled()
    first.simulate(backend="c", params={"seal.c": 1e5}, start={"hammer.v": 3.0}, rtol=1e-6,
                   method="bdf", max_step=1e-5, n_out=11)
    assert Simulator.of(first).compiled() is lib and build.BUILDS == before + 1
    # another instance of the same rig: the library comes from the disk cache
    second = paper_rig()
    second.simulate(backend="c")
    assert build.BUILDS == before + 1
    # found by the rig's fingerprint, without code generation: the same library
    assert Simulator.of(second).compiled().path.samefile(lib.path)
    assert sorted(f.name for f in tmp_path.iterdir()) == sorted(
        [lib.path.name, f"fp-{build.fingerprint(second.compile())}.so"])


class _Blowup(pdbfs.Rig):
    def declare(self):
        self.m = Mass(m=1.0)
        self.f = Force(function=lambda t: 1.0 / (0.001 - t) ** 3)   # blows up at 1 ms
        self.connect(self.m.flange_a, self.f.flange)


def test_solver_failure_reports_time_and_cause(rig):
    with pytest.raises(SolverError, match=r"failed after t = 0\.00(099\d*|1) s \(of 0\.002 s\): "
                                          r"too many steps"):
        _Blowup().simulate(0.002, n_out=2001, backend="c", max_num_steps=20000, rtol=1e-9)
    # at the explicit method's default rtol its steps fall below roundoff first
    with pytest.raises(SolverError, match=r"failed after t = 0\.00(099\d*|1) s \(of 0\.002 s\): "
                                          r"the error test failed repeatedly.*below roundoff"):
        _Blowup().simulate(0.002, n_out=2001, backend="c", max_num_steps=20000)
    with pytest.raises(SolverError, match=r"failed after t = [0-9.e-]+ s \(of 0\.02 s\): too many "
                                          r"steps.*CVODE: 5 internal steps"):
        rig.simulate(backend="c", method="adams", max_num_steps=5)
    with pytest.raises(SolverError, match=r"failed after t = [0-9.e-]+ s \(of 0\.02 s\): too many "
                                          r"steps.*explicit Runge-Kutta: 2 steps without"):
        rig.simulate(backend="c", method="erk", max_num_steps=2)


def test_nan_in_the_solution_is_a_solver_error(rig, monkeypatch):
    c = Simulator.of(rig).compiled()
    real = type(c).run

    def poisoned(self, *a, **k):
        X, st = real(self, *a, **k)
        X[1, -3:] = np.nan
        return X, st
    real_with_summary = type(c).run_summary

    def poisoned_with_summary(self, *a, **k):   # the run and its summary, states made at once
        X, st, *rest = real_with_summary(self, *a, **k)
        if X is not None:
            X[1, -3:] = np.nan
        return (X, st, *rest)
    real_states = batch.KeptRun.states

    def poisoned_states(self):                   # the default path: states made when read
        X, code, message = real_states(self)
        X[1, -3:] = np.nan
        return X, code, message
    monkeypatch.setattr(type(c), "run", poisoned)
    monkeypatch.setattr(type(c), "run_summary", poisoned_with_summary)
    monkeypatch.setattr(batch.KeptRun, "states", poisoned_states)
    with pytest.raises(SolverError, match=r"NaN or infinite at t = 0\.0199"):
        rig.simulate(backend="c", method="adams")
    res = rig.simulate(backend="c")
    assert res.settings["method"] == "erk"
    with pytest.raises(SolverError, match=r"NaN or infinite at t = 0\.0199"):
        res["oil.pressure"]


def test_cli_and_sweep_take_the_backend(rig, tmp_path, capsys):
    assert main(["simulate", "--backend", "c", "--json", "--out", str(tmp_path)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["peak_pressure"] == pytest.approx(rig.simulate(backend="casadi").summary()["peak_pressure"],
                                                     rel=1e-6)
    res = pdbfs.sweep(rig, {"hammer.v0": [2.0, 4.0]}, backend="c")   # the C summary driver
    for pt in res:
        single = rig.simulate(params=pt.params, backend="c").summary()
        for k in ("peak_pressure", "time_of_peak", "pulse_duration"):
            assert pt.summary[k] == pytest.approx(single[k], rel=1e-6), k


def test_run_reports_solver_statistics(rig):
    """steps, evaluations and root events of one run, as CVODE counted them;
    the root events are at least the contact onsets and separations."""
    c = Simulator.of(rig).compiled()
    p = Simulator.of(rig).param_vector()
    x0 = Simulator.of(rig).start_vector(p)
    contacts = rig.simulate(0.02, n_out=4001).crossings("contact.d", 0.0)
    assert len(contacts) >= 5          # 3 blows of the hammer's chatter: separations and onsets
    for method, name in (("adams", "adams/fixed-point"), ("bdf", "bdf/newton-dense")):
        X, st = c.run(T, x0, p, 1e-8, 1e-10, method=method)
        assert st.ok and set(st.stats) == set(batch.STAT_KEYS)
        s = st.stats
        assert all(isinstance(s[k], int) for k in ("steps", "rhs_evals", "jac_evals", "root_events"))
        assert s["method"] == name and isinstance(s["wall_time"], float) and s["wall_time"] > 0
        assert s["steps"] > 100 and s["rhs_evals"] >= s["steps"]
        assert s["root_events"] >= len(contacts) and s["root_events"] == st.roots
        assert (s["jac_evals"] > 0) == (method == "bdf")
    # Newton on a banded Jacobian: the split piston's chain, from 40 states on
    big = split_piston_rig(20)
    sim = Simulator.of(big)
    pb = sim.param_vector()
    _, st = sim.compiled().run(T, sim.start_vector(pb), pb, 1e-8, 1e-10)
    assert st.ok and st.stats["method"] == "adams/newton-band" and st.stats["jac_evals"] > 0
    # a failed run still counts what it did
    _, st = c.run(T, x0, p, 1e-8, 1e-10, max_num_steps=5)
    assert st.code == batch.RC_TOO_MUCH_WORK and st.stats["steps"] == 5
