"""Issue 14's cases, each a regression test: the right number, or a clear
word that there is none; bad input gets one line, exit status 2, before any
work, and leaves nothing behind."""
import json
import os
import signal
import subprocess
import sys
import time
import warnings

import casadi as ca
import numpy as np
import pytest

import pdbfs
from pdbfs import Rig
from pdbfs.components import Mass, Position
from pdbfs.errors import ConnectError, DataError, PulseIncompleteWarning, SampleTooSmallWarning
from pdbfs.models import drop_rig, paper_rig
from pdbfs.studies import Grid


def cli(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=timeout)


def one_line_error(r, *fragments):
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error:"), r.stderr
    for f in fragments:
        assert f in lines[0], lines[0]
    assert "Traceback" not in r.stderr


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.fixture(scope="module")
def reference(rig):
    return rig.simulate().summary()


# -- the summary does not depend on the output grid or the horizon -------------------------
@pytest.mark.parametrize("kw", [dict(n_out=3), dict(n_out=21), dict(n_out=2001),
                                dict(n_out=20001), dict(t_end=0.02, n_out=7),
                                dict(t_end=2.0), dict(t_end=100.0)])
def test_summary_is_the_same_whatever_the_grid_and_horizon(rig, reference, kw):
    s = rig.simulate(**kw).summary()
    assert s["complete"] is True
    for k, v in reference.items():
        assert s[k] == pytest.approx(v, rel=1e-6), (kw, k)
    assert 0.9 < s["restitution_coefficient"] < 0.95       # the paper's range, never above 1


def test_compiled_backend_and_its_summary_driver_agree(rig, reference):
    s = rig.simulate(n_out=21, backend="c").summary()
    for k, v in reference.items():
        assert s[k] == pytest.approx(v, rel=1e-6), k
    sw = pdbfs.sweep(rig, Grid({"hammer.v0": [2.73]}), backend="c", progress=False)
    for k in ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
              "max_piston_displacement", "restitution_coefficient"):
        assert sw[0].summary[k] == pytest.approx(reference[k], rel=1e-6), k
    assert sw[0].summary["complete"] is True


# -- a pulse cut off by the horizon says so ---------------------------------------------------
def test_cut_off_pulse_is_not_reported_as_complete(rig):
    with pytest.warns(PulseIncompleteWarning, match=r"t_end = 0.02 s.*use t_end >= "):
        cut = rig.simulate(params={"oil.n": 1.5}).summary()
    assert cut["complete"] is False
    assert cut["pulse_duration"] is None and cut["restitution_coefficient"] is None
    whole = rig.simulate(0.06, params={"oil.n": 1.5}).summary()
    assert whole["complete"] is True and whole["pulse_duration"] > 0.02
    assert cut["peak_pressure"] == pytest.approx(whole["peak_pressure"], rel=1e-6)


def test_cut_off_pulse_in_the_json_and_on_stderr(tmp_path):
    r = cli("simulate", "--set", "oil.n=1.5", "--json", "--out", str(tmp_path))
    assert r.returncode == 0
    doc = json.loads(r.stdout)
    assert doc["complete"] is False and doc["pulse_duration"] is None
    warn = [l for l in r.stderr.splitlines() if l.startswith("pdbfs: warning:")]
    assert len(warn) == 1 and "use t_end >=" in warn[0]


def test_no_pulse_has_no_time_of_peak_and_no_infinity(tmp_path):
    r = cli("simulate", "--set", "hammer.v0=0", "--json", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    assert "Infinity" not in r.stdout and "NaN" not in r.stdout
    doc = json.loads(r.stdout)
    assert doc["peak_pressure"] is None and doc["time_of_peak"] is None   # no pulse, no peak
    assert "no pulse" in r.stderr
    assert doc["restitution_coefficient"] is None


def test_drop_rig_reports_the_first_blow_and_every_blow():
    res = drop_rig().simulate(1.5, n_out=30001)
    s = res.summary()
    durations = s["impact_durations"]
    assert s["impact_count"] == len(durations) >= 3
    assert s["pulse_duration"] == pytest.approx(durations[0], rel=1e-9)
    assert 0.008 < durations[0] < 0.02             # one blow, not the sum of three
    assert s["peak_pressure"] == pytest.approx(s["impact_peak_pressures"][0], rel=1e-12)
    assert s["impact_peak_pressures"][1] < s["peak_pressure"]


# -- traces: columns by name, units, headers ---------------------------------------------------
@pytest.fixture(scope="module")
def own_results(tmp_path_factory):
    out = tmp_path_factory.mktemp("own")
    r = cli("simulate", "--set", "oil.k=3e8", "--out", str(out))
    assert r.returncode == 0, r.stderr
    return out / "results.csv"


def test_pdbfs_results_csv_is_a_trace(own_results):
    cal = pdbfs.calibrate(paper_rig(), own_results, ["oil.k"], signal="oil.pressure")
    assert cal.params["oil.k"] == pytest.approx(3e8, rel=1e-4)
    assert not cal.at_bounds


def test_many_columns_and_no_way_to_choose_is_an_error(tmp_path, own_results):
    import pandas as pd
    df = pd.read_csv(own_results)
    df[["time [s]", "hammer.s [m]", "piston.s [m]"]].to_csv(tmp_path / "t.csv", index=False)
    with pytest.raises(DataError, match="2 signal columns"):
        pdbfs.studies.read_trace(tmp_path / "t.csv")
    with pytest.raises(DataError, match="no column 'oil.pressure'"):
        pdbfs.calibrate(paper_rig(), tmp_path / "t.csv", ["oil.k"])


def _pulse(tmp_path, header, t_scale, y_scale, name="m.csv"):
    res = paper_rig().simulate(params={"hammer.v0": 2.5})
    path = tmp_path / name
    rows = np.column_stack([res.t[::10] * t_scale, res["oil.pressure"][::10] * y_scale])
    with open(path, "w") as fh:
        if header:
            fh.write(header + "\n")
        np.savetxt(fh, rows, delimiter=",")
    return path


def test_units_in_the_header_are_converted(tmp_path):
    path = _pulse(tmp_path, "time [ms],oil.pressure [kPa]", 1e3, 1e-3)
    tr = pdbfs.studies.read_trace(path)
    assert tr.t[-1] == pytest.approx(0.02) and tr.unit == "Pa"
    cal = pdbfs.calibrate(paper_rig(), path, ["hammer.v0"])
    assert cal.params["hammer.v0"] == pytest.approx(2.5, rel=1e-5)


@pytest.mark.parametrize("header,fragment", [("time [ms],p [furlong]", "unknown unit 'furlong'"),
                                             ("time [kPa],p [Pa]", "must be time")])
def test_unknown_or_wrong_units_are_refused(tmp_path, header, fragment):
    path = _pulse(tmp_path, header, 1e3, 1.0)
    with pytest.raises(DataError, match=fragment):
        pdbfs.studies.read_trace(path)


def test_implausible_times_without_a_unit_get_a_hint(tmp_path):
    path = _pulse(tmp_path, "time,pressure", 1e3, 1.0)       # ms, but no unit said
    r = cli("calibrate", "--trace", str(path), "--free", "hammer.v0", timeout=60)
    one_line_error(r, "without a unit", "time [ms]")


def test_a_trace_without_a_header_keeps_its_first_row(tmp_path):
    path = _pulse(tmp_path, None, 1.0, 1.0)
    tr = pdbfs.studies.read_trace(path)
    assert len(tr) == 201 and tr.t[0] == 0.0


def test_calibration_cost_follows_the_trace_not_the_horizon(tmp_path):
    """A 2 s trace (a long record around one pulse) fits on a grid of tens
    of thousands of points, not 400,000."""
    from pdbfs.studies.fitting.signal_model import MAX_COARSE, MAX_FINE, model_grid
    grid = model_grid(20.0, 5e-6, 0.06)
    assert grid.size <= MAX_FINE + MAX_COARSE + 1 and grid[-1] == 20.0
    assert np.all(np.diff(grid[grid <= 0.06]) == pytest.approx(5e-6))


# -- sensitivity with too small a sample ------------------------------------------------------
def test_sensitivity_says_when_the_sample_is_too_small():
    with pytest.warns(SampleTooSmallWarning, match="too small"):
        s = pdbfs.sensitivity(paper_rig(), {"hammer.v0": (1.5, 5.5), "oil.k": (1e8, 1e9)},
                              n=8, progress=False)
    assert s.to_dict()["reliable"] is False and s.problems()


# -- bad input: one line, exit 2, before any work, nothing left ----------------------------------
@pytest.mark.parametrize("command", [["simulate"], ["sweep", "--set", "hammer.v0=2,3"],
                                     ["reproduce", "--figures", "fig5"],
                                     ["calibrate", "--trace", "TRACE", "--free", "oil.k"]])
def test_out_naming_a_file_is_refused_before_any_work(tmp_path, own_results, command):
    target = tmp_path / "a_file"
    target.write_text("keep me\n")
    args = [str(own_results) if a == "TRACE" else a for a in command]
    t0 = time.time()
    r = cli(*args, "--out", str(target))
    one_line_error(r, str(target), "not a folder")
    assert target.read_text() == "keep me\n" and time.time() - t0 < 30


def test_out_that_cannot_be_made_is_refused(tmp_path):
    one_line_error(cli("simulate", "--out", "/proc/x"), "/proc/x")
    assert not (tmp_path / "x").exists()


def test_export_fmu_to_a_folder_or_nowhere_is_refused(tmp_path):
    one_line_error(cli("export-fmu", "-o", "/proc/x.fmu"), "/proc/x.fmu")
    folder = tmp_path / "existing"
    folder.mkdir()
    one_line_error(cli("export-fmu", "-o", str(folder)), "is a folder")
    assert list(tmp_path.iterdir()) == [folder] and not list(folder.iterdir())


def test_ctrl_c_on_a_sweep_is_one_line_and_the_same_command_resumes(tmp_path):
    args = [sys.executable, "-m", "pdbfs.cli", "sweep", "--sample", "lhs:2000",
            "--range", "hammer.v0=2:4", "--out", str(tmp_path / "sw"), "--chunk", "20", "--t-end", "1",
            "--workers", "1", "--quiet"]
    p = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    chunks = tmp_path / "sw" / "chunks"
    deadline = time.time() + 120
    while time.time() < deadline and len(list(chunks.glob("chunk-*"))) < 2:
        time.sleep(0.1)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "points are saved" in lines[0] and "resumes" in lines[0], err
    assert "Traceback" not in err


def test_a_prescribed_motion_is_evaluated_not_a_casadi_error():
    class Driven(Rig):
        def declare(self):
            self.src = Position(function=lambda t: 0.01 * (1 - ca.cos(100 * t)))
            self.m = Mass(m=2.0)
            self.connect(self.src.flange, self.m.flange_a)
    for backend in ("casadi", "c"):
        res = Driven().simulate(0.1, n_out=11, backend=backend)
        assert res["m.a"] == pytest.approx(100 * np.cos(100 * res.t), abs=1e-9)   # s'' exactly
        assert res.stats["steps"] == 0


def test_connect_errors_name_components_not_objects():
    class Wrong(Rig):
        def declare(self):
            self.hammer = Mass(m=1.0)
            self.other = Mass(m=1.0)
            self.connect(self.hammer, self.other.flange_a)
    with pytest.raises(ConnectError) as err:
        Wrong().compile()
    assert "hammer (Mass)" in str(err.value) and "object at 0x" not in str(err.value)


def test_sweep_like_simulate_long_horizon_compiled_and_auto_method(tmp_path):
    r = cli("sweep", "--set", "hammer.v0=2,3", "--t-end", "10", "--backend", "c", "--json",
            "--no-plot", "--out", str(tmp_path / "s"))
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["failed"] == 0
    import argparse
    from pdbfs.cli import build_parser
    ap = build_parser()
    assert ap.parse_args(["sweep", "--set", "hammer.v0=2"]).method == \
        ap.parse_args(["simulate"]).method == "auto"
    assert isinstance(ap, argparse.ArgumentParser)


def test_solver_statistics_for_both_back_ends(rig):
    # "auto": Adams through CasADi, the explicit Runge-Kutta method compiled (fewer, longer steps)
    for backend, method, steps in (("casadi", "adams", 100), ("c", "erk/dop853", 50)):
        st = rig.simulate(backend=backend).stats
        assert st["backend"] == backend and st["method"].startswith(method)
        assert st["steps"] > steps and st["rhs_evals"] >= st["steps"] and st["wall_time"] > 0
    assert rig.simulate(backend="c").stats["root_events"] >= 2      # contact onset, separation


def test_warnings_do_not_leak_from_sweeps():
    with warnings.catch_warnings():
        warnings.simplefilter("error", PulseIncompleteWarning)
        res = pdbfs.sweep(paper_rig(), Grid({"oil.n": [1.0, 1.5]}), backend="casadi",
                          progress=False, workers=1)
    assert [p.summary["complete"] for p in res] == [True, False]
    assert os.environ.get("PDBFS_NEVER_SET") is None


def test_a_very_long_run_of_repeated_blows_says_how_far_blows_are_listed(monkeypatch):
    """Memory stays bounded on any horizon: the summary keeps at most
    MAX_POINTS points (3 s here) and says so; what it lists is exact."""
    import pdbfs.simulation.results.summary_run as SR
    monkeypatch.setattr(SR, "MAX_POINTS", 300_000)
    whole = drop_rig().simulate(1.5, n_out=30001).summary()
    with pytest.warns(pdbfs.PdbfsWarning, match="blows are listed up to t = 3 s of 6 s"):
        long = drop_rig().simulate(6.0, n_out=2001).summary()
    assert max(long["impact_times"]) <= 3.0 and long["impact_count"] > whole["impact_count"]
    for k in ("impact_times", "impact_durations", "impact_peak_pressures"):
        assert long[k][:3] == pytest.approx(whole[k], rel=1e-6), k
