"""Sweeps whose pulses are cut off at t_end: the summary driver follows such a
pulse past t_end itself (native/c/library/pdbfs_summary.c, follow()) and answers what
Result.summary() answers (summary.py follows it in Python), point by point;
only CVODE's methods, and a point the driver could not follow, go to
Result.summary()."""
import warnings

import numpy as np
import pytest

import pdbfs
from pdbfs.models import paper_hydraulic_oil_rig, paper_rig, split_piston_rig
from pdbfs.simulation.run import compiled
from pdbfs.studies.sweeps import runner

KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
        "max_piston_displacement", "restitution_coefficient", "complete")


def result_summary(rig, t_end, params, method=None):
    kw = {"method": method} if method else {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return rig.simulate(t_end, params=params, backend="c", **kw).summary()


def assert_same(res, rig, t_end, method=None):
    for pt in res:
        ref = result_summary(rig, t_end, pt.params, method)
        for k in KEYS:
            got, want = pt.summary[k], ref.get(k)
            if want is None:
                assert got is None or got != got, (pt.params, t_end, k, got)
            else:
                assert got == pytest.approx(want, rel=1e-6), (pt.params, t_end, k)


@pytest.fixture
def no_python_points(monkeypatch):
    """A sweep in which every point is the driver's (none is run again in Python)."""
    def refuse(self, P, ok, *a):
        if ok.any():
            raise AssertionError(f"{int(ok.sum())} points run again in Python")
    monkeypatch.setattr(runner.Runner, "_run_points", refuse)


@pytest.mark.parametrize("t_end", [0.001, 0.0055, 0.006, 0.009, 0.012])
def test_cut_off_pulses_are_the_drivers_and_as_result_summary(t_end, no_python_points):
    rig = paper_rig()
    res = pdbfs.sweep(rig, {"hammer.v0": [1.5, 3.0, 5.5]}, t_end=t_end, workers=1)
    assert all(pt.summary["complete"] is False for pt in res)
    assert_same(res, rig, t_end)


def test_a_higher_pressure_after_t_end_leaves_no_peak(no_python_points):
    """At 5.5 m/s the pressure has a maximum at 5.24 ms and a higher one
    after 6 ms: cut off at 6 ms, its highest pressure so far is no peak."""
    rig = paper_rig()
    pt = next(iter(pdbfs.sweep(rig, {"hammer.v0": [5.5]}, t_end=0.006, workers=1)))
    assert pt.summary["peak_pressure"] is None and pt.summary["time_of_peak"] is None
    later = result_summary(rig, 0.02, {"hammer.v0": 5.5})
    assert later["time_of_peak"] > 0.006
    # and cut off after that peak, the peak is the run's own
    pt = next(iter(pdbfs.sweep(rig, {"hammer.v0": [5.5]}, t_end=0.009, workers=1)))
    assert pt.summary["peak_pressure"] == pytest.approx(later["peak_pressure"], rel=1e-6)
    assert pt.summary["complete"] is False


@pytest.mark.parametrize("make", [lambda: split_piston_rig(n=3), paper_hydraulic_oil_rig])
def test_other_rigs_cut_off(make, no_python_points):
    rig = make()
    res = pdbfs.sweep(rig, {"hammer.v0": [2.0, 5.0]}, t_end=0.004, workers=1)
    assert_same(res, rig, 0.004)


def test_cvode_methods_and_failed_follows_go_to_result_summary(monkeypatch):
    rig = paper_rig()
    res = pdbfs.sweep(rig, {"hammer.v0": [3.0, 5.5]}, t_end=0.006, method="adams",
                      backend="c", workers=1)
    assert_same(res, rig, 0.006, method="adams")
    # a point whose pulse the driver could not follow: Result.summary()'s answer
    real = compiled.CompiledODE.summaries

    def unfollowed(self, P, *a, **kw):
        values, codes, msgs = real(self, P, *a, **kw)
        codes[:] = compiled.RC_FOLLOW
        values[:] = np.nan
        return values, codes, msgs
    monkeypatch.setattr(compiled.CompiledODE, "summaries", unfollowed)
    res = pdbfs.sweep(rig, {"hammer.v0": [3.0, 5.5]}, t_end=0.006, workers=1)
    assert not any(pt.error for pt in res)
    assert_same(res, rig, 0.006)


def test_a_maximum_at_t_end_is_no_peak_though_the_next_sample_is_lower(no_python_points):
    """Cut off 2 us before the peak: the pressure still rises at t_end, and the
    first sample past it (10 us grid) already lies beyond the peak, lower.
    Neither Result.summary() nor the driver calls the value at t_end a peak."""
    rig = paper_rig()
    full = rig.simulate(0.02)
    t_pk = full.summary()["time_of_peak"]
    t_end = t_pk - 2e-6
    after = 1e-5 * (np.floor(t_end / 1e-5 + 1e-6) + 1)
    # the premise, on the 20 ms run
    assert full.value_at("oil.pressure", after) < full.value_at("oil.pressure", t_end)
    ref = result_summary(rig, t_end, {})
    assert ref["peak_pressure"] is None and ref["time_of_peak"] is None
    pt = next(iter(pdbfs.sweep(rig, {"hammer.v0": [full.params["hammer.v0"]]}, t_end=t_end,
                               workers=1)))
    assert pt.summary["peak_pressure"] is None and pt.summary["complete"] is False
