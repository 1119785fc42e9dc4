"""pdbfs.sweep and `pdbfs sweep`: one compiled rig, many points."""
import csv
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.studies import SweepResult, points_of

V = [1.87, 2.73, 4.23, 5.50]


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


def test_grid_and_zip_points():
    pts = points_of({"a": [1, 2], "b": [10, 20, 30]})
    assert len(pts) == 6 and pts[0] == {"a": 1, "b": 10} and pts[-1] == {"a": 2, "b": 30}
    pts = points_of({"a": [1, 2], "b": [10, 20]}, grid=False)
    assert pts == [{"a": 1, "b": 10}, {"a": 2, "b": 20}]
    with pytest.raises(ParameterError, match="equal length.*a: 2, b: 3"):
        points_of({"a": [1, 2], "b": [1, 2, 3]}, grid=False)
    with pytest.raises(ParameterError, match="no values given for a"):
        points_of({"a": []})
    with pytest.raises(ParameterError, match="non-empty dict"):
        points_of({})


def test_sweep_matches_single_runs_and_reuses_the_compiled_rig(rig):
    dae = rig.compile()
    sim = Simulator.of(rig)
    res = pdbfs.sweep(rig, {"hammer.v0": V}, backend="casadi")
    assert isinstance(res, SweepResult) and len(res) == 4 and not res.failed
    assert rig.compile() is dae and Simulator.of(rig) is sim   # nothing rebuilt
    for pt, v in zip(res, V):
        single = rig.simulate(0.02, params={"hammer.v0": v}, backend="casadi").summary()
        assert pt.params == {"hammer.v0": v}
        for k, val in single.items():
            assert pt.summary[k] == pytest.approx(val, rel=1e-12, nan_ok=True)
    # the physics of Fig. 6: magnitude governed by the impact velocity, ~ v
    peaks = res.values("peak_pressure")
    assert np.all(np.diff(peaks) > 0)
    ratio = peaks / np.array(V)
    assert np.ptp(ratio) / ratio.mean() < 0.1


def test_parallel_sweep_gives_the_serial_answer(rig):
    values = {"hammer.v0": [2.0, 3.0, 4.0], "oil.k": [1.5e8, 2.228e8, 4e8]}
    serial = pdbfs.sweep(rig, values, workers=1)
    parallel = pdbfs.sweep(rig, values, workers=2)
    assert parallel.workers == 2 and serial.workers == 1
    for a, b in zip(serial, parallel):
        assert a.params == b.params
        assert a.summary["peak_pressure"] == b.summary["peak_pressure"]
        assert a.summary["pulse_duration"] == b.summary["pulse_duration"]
    # Fig. 9: stiffer oil, higher and shorter pulse, at every velocity
    for v in values["hammer.v0"]:
        row = [p for p in serial if p.params["hammer.v0"] == v]
        assert np.all(np.diff([p["peak_pressure"] for p in row]) > 0)
        assert np.all(np.diff([p["pulse_duration"] for p in row]) < 0)


def test_failed_points_are_reported_and_the_others_come_back(rig, tmp_path):
    res = pdbfs.sweep(rig, {"hammer.v0": [2.73, 1e150, 4.23], "seal.c": [2.556e4, -1.0]},
                      workers=2, backend="casadi")
    assert len(res) == 6
    bad_c = [p for p in res if p.params["seal.c"] < 0]
    assert all(p.error_type == "ParameterError" and "seal.c" in p.error for p in bad_c)
    blown = [p for p in res if p.params["hammer.v0"] == 1e150 and p.params["seal.c"] > 0]
    assert blown[0].error_type == "SolverError" and "solver failed" in blown[0].error
    good = res.ok
    assert [p.params["hammer.v0"] for p in good] == [2.73, 4.23]
    assert good[0]["peak_pressure"] == pytest.approx(
        rig.simulate(0.02, backend="casadi").summary()["peak_pressure"], rel=1e-12)
    with pytest.raises(KeyError, match="failed"):
        bad_c[0]["peak_pressure"]
    assert math.isnan(res.values("peak_pressure")[1])
    path = res.to_csv(tmp_path / "s.csv")
    rows = list(csv.DictReader(open(path)))
    assert len(rows) == 6
    assert "peak_pressure [Pa]" in rows[0] and rows[0]["error"] == ""
    assert rows[1]["error"].startswith("ParameterError: seal.c = -1")
    assert float(rows[0]["peak_pressure [Pa]"]) == good[0]["peak_pressure"]


def test_sweep_rejects_bad_input_up_front(rig):
    with pytest.raises(ParameterError, match="'hammer.v00'.*did you mean hammer.v0"):
        pdbfs.sweep(rig, {"hammer.v00": [1, 2]})
    with pytest.raises(ParameterError, match="both swept and fixed"):
        pdbfs.sweep(rig, {"hammer.v0": [1, 2]}, params={"hammer.v0": 3})
    with pytest.raises(ParameterError, match="workers"):
        pdbfs.sweep(rig, {"hammer.v0": [1, 2]}, workers=0)
    with pytest.raises(ParameterError, match="t_end"):
        pdbfs.sweep(rig, {"hammer.v0": [1, 2]}, t_end=-1)
    with pytest.raises(ParameterError, match="unknown rig 'nope'"):
        pdbfs.sweep("nope", {"hammer.v0": [1, 2]})


def test_trajectories_are_full_results(rig):
    res = pdbfs.sweep(rig, {"seal.c": [2.556e4, 2.556e6]}, t_end=0.03, n_out=3001,
                      trajectories=True, workers=2, backend="casadi")
    r0, r1 = res[0].result, res[1].result
    assert r0["oil.pressure"].shape == (3001,)
    t_pk, p_pk = r0.peak("oil.pressure")
    assert p_pk == pytest.approx(res[0]["peak_pressure"], rel=1e-9)
    assert r0.value_at("oil.pressure", t_pk) == pytest.approx(p_pk, rel=1e-9)
    # Fig. 8: heavy seal friction flattens and stretches the pulse
    assert r1["oil.pressure"].max() < 0.5 * r0["oil.pressure"].max()
    assert r1["oil.pressure"][-1] > 0.1 * r1["oil.pressure"].max()  # still pressed at 30 ms
    fig = res.plot()
    assert len(fig.axes[0].lines) == 2


def test_trajectories_of_compiled_runs_come_back_from_worker_processes(rig):
    """The default back end's Result makes its states when first read (the
    run kept in the library); a worker process sends its Results with their
    states made, and they are the runs' own (they failed to pickle)."""
    res = pdbfs.sweep(rig, {"hammer.v0": [2.0, 3.0]}, trajectories=True, workers=2,
                      progress=False)
    assert res.workers == 2 and res[1].result.settings["backend"] == "c"
    alone = rig.simulate(params={"hammer.v0": 3.0})
    assert np.array_equal(res[1].result["oil.pressure"], alone["oil.pressure"])
    assert res[1].result.summary() == alone.summary()


def test_compiled_trajectories_come_back_from_worker_processes(rig):
    """A compiled run's states are made from its record in the library only
    when read; a Result sent back from a forked worker makes them there (it
    failed to pickle: a lambda), the same numbers as a run in this process."""
    res = pdbfs.sweep(rig, {"hammer.v0": V}, trajectories=True, workers=2, backend="c")
    assert res.where == "2 processes" and len(res.failed) == 0
    for k, v in enumerate(V):
        here = pdbfs.simulate(rig, params={"hammer.v0": v}, backend="c",
                              method=res[k].result.settings["method"])
        assert np.array_equal(res[k].result["oil.pressure"], here["oil.pressure"])
    # a lazy Result travels with its states made (and loses nothing else)
    import pickle
    lazy = pdbfs.simulate(rig, backend="c", method="erk")
    assert lazy._states is None
    back = pickle.loads(pickle.dumps(lazy.detached()))
    assert "_make_states" not in back and np.array_equal(back["_states"], lazy._X)


def test_cli_sweep_writes_csv_and_plot(tmp_path, capsys):
    out = tmp_path / "sw"
    code = main(["sweep", "--set", "hammer.v0=1.87,2.73", "--set", "oil.k=2e8:4e8:2",
                 "--out", str(out), "--quiet"])
    assert code == 0
    rows = list(csv.DictReader(open(out / "sweep.csv")))
    assert [(float(r["hammer.v0"]), float(r["oil.k"])) for r in rows] == [
        (1.87, 2e8), (1.87, 4e8), (2.73, 2e8), (2.73, 4e8)]
    assert (out / "sweep.png").stat().st_size > 10000
    assert "4 points, 0 failed;" in capsys.readouterr().out
    assert main(["sweep", "--set", "hammer.v0=1,x"]) == 2
    assert "values must be numbers" in capsys.readouterr().err
    assert main(["sweep", "--set", "nope=1,2", "--out", str(out)]) == 2
    assert "unknown parameter 'nope'" in capsys.readouterr().err
    assert main(["sweep", "--set", "hammer.v0=1,2", "--set", "seal.c=1", "--zip",
                 "--out", str(out)]) == 2


def test_points_refused_by_limits_or_conditions_are_named_among_good_ones():
    # the runner checks a chunk's values and the components' conditions all at
    # once; a point refused is named as a single run would name it
    from pdbfs.models import paper_hydraulic_rig
    rig = paper_hydraulic_rig()
    values = [-5e4, 0.0, 5e6, float("nan"), 1e3]
    p0 = [0.0, 0.0, 0.0, 0.0, 2e3]
    res = pdbfs.sweep(rig, {"oil.p_vap": values, "oil.p0": p0}, grid=False, progress=False,
                      workers=2, chunk_size=2)
    errors = [p.error for p in res]
    assert [p.error_type for p in res] == ["ParameterError", None, "ParameterError",
                                           "ParameterError", None]
    assert errors[0].startswith("oil.p_vap = -50000 Pa: must be >= 0")
    assert errors[2].startswith("oil (Volume): the oil would start as vapour")
    assert "oil.p_vap = 5e+06 Pa, oil.p0 = 0 Pa" in errors[2]
    assert errors[3].startswith("oil.p_vap = nan: must be finite")
    assert not errors[1] and not errors[4]
    for i in (1, 4):
        single = rig.simulate(params={"oil.p_vap": values[i], "oil.p0": p0[i]}).summary()[
            "peak_pressure"]
        assert res[i]["peak_pressure"] == single
    assert list(res.frame["point"]) == list(range(len(values)))


def test_the_chunk_check_agrees_with_check_value_value_by_value():
    # within_limits (a chunk at once) and check_value (one value, its message)
    # hold the same rules: the runner trusts the first and names with the second
    from pdbfs.modelling import Parameter, check_value, within_limits
    specs = [Parameter(1.0, "m", "a length", positive=True),
             Parameter(0.0, "Pa", "a pressure", min=0.0, max=1e9),
             Parameter(0.5, "1", "a ratio", min=-1.0)]
    values = np.array([-2.0, -1.0, 0.0, 1e-300, 0.5, 1e9, 2e9, np.inf, -np.inf, np.nan])
    for spec in specs:
        expected = []
        for v in values:
            try:
                check_value(v, "x", spec)
                expected.append(True)
            except ParameterError:
                expected.append(False)
        assert within_limits(values, spec).tolist() == expected
