"""The explicit Runge-Kutta method of the compiled backend (method="erk",
c/pdbfs_erk.c: Dormand & Prince 8(5,3) with dense output, restarted at the
roots of the rig's event indicators): against a tight event-located
reference written by hand (paper_equations.py), against CVODE, and chosen
by method="auto" where the rig is not stiff."""
import numpy as np
import pytest

import pdbfs
from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator

from paper_equations import TABLE1, pressure, reference

T = np.linspace(0.0, 0.02, 2001)


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.fixture(scope="module")
def tight():
    X = reference(T)[0]
    k = int(np.argmax(pressure(X, TABLE1)))
    fine = np.linspace(T[k - 1], T[k + 1], 4001)           # the reference's own peak
    Xf = reference(np.r_[np.linspace(0.0, T[k - 1], 20, endpoint=False), fine])[0][:, 20:]
    pf = pressure(Xf, TABLE1)
    return X, float(fine[np.argmax(pf)]), float(pf.max())


def test_erk_meets_the_tight_reference_on_the_trace_and_the_peak(rig, tight):
    X, t_pk, p_pk = tight
    r = rig.simulate(t_out=T, backend="c", method="erk")
    assert r.stats["method"] == "erk/dop853"
    p_ref = pressure(X, TABLE1)
    assert np.max(np.abs(r["oil.pressure"] - p_ref)) < 1e-6 * p_ref.max()
    t, v = r.peak("oil.pressure")
    assert abs(v - p_pk) < 1e-7 * p_pk
    assert abs(t - t_pk) < 1e-8
    # far fewer steps than CVODE's Adams for the same accuracy
    a = rig.simulate(t_out=T, backend="c", method="adams")
    assert r.stats["steps"] < a.stats["steps"] / 2


def test_erk_agrees_with_cvode_state_by_state(rig):
    e = rig.simulate(t_out=T, backend="c", method="erk", rtol=1e-10, atol=1e-12)
    a = rig.simulate(t_out=T, backend="casadi", method="adams", rtol=1e-10, atol=1e-12)
    for k, name in enumerate(rig.compile().x_names):
        scale = np.max(np.abs(a._X[k]))
        assert np.max(np.abs(e._X[k] - a._X[k])) < 1e-6 * scale, name


def test_erk_restarts_at_each_kink_the_reference_locates(rig):
    """contact onsets and separations and the oil going slack: as many roots as
    CVODE's root finding counts, and the contact's crossings where a tight
    CVODE run puts them"""
    e = rig.simulate(t_out=T, backend="c", method="erk")
    a = rig.simulate(t_out=T, backend="c", method="adams")
    assert e.stats["root_events"] == a.stats["root_events"] >= 5
    tight = rig.simulate(t_out=T, backend="casadi", method="adams", rtol=1e-12, atol=1e-14)
    ce, ct = e.crossings("contact.d", 0.0), tight.crossings("contact.d", 0.0)
    assert len(ce) == len(ct) >= 3
    assert np.max(np.abs(ce - ct)) < 1e-9


def test_output_grid_does_not_change_the_solution(rig):
    coarse = rig.simulate(t_out=np.array([0.0, 5e-3, 0.02]), backend="c", method="erk")
    fine = rig.simulate(t_out=np.r_[np.linspace(0, 5e-3, 501), 0.02], backend="c", method="erk")
    assert np.array_equal(coarse._X[:, 1], fine._X[:, 500])


def test_auto_picks_erk_in_the_compiled_backend_only_where_the_rig_is_not_stiff(rig):
    assert rig.simulate(n_out=11).settings["method"] == "erk"
    assert rig.simulate(n_out=11, backend="casadi").settings["method"] == "adams"
    sim = Simulator.of(rig)
    p = sim.param_vector({"seal.c": 1e9})                  # a fast mode that decays: stiff
    assert sim.resolve_method("auto", p, sim.start_vector(p), 0.02, "c") == "bdf"


def test_erk_needs_the_compiled_backend(rig):
    with pytest.raises(ParameterError, match="erk.*compiled backend"):
        rig.simulate(backend="casadi", method="erk")


def test_the_summary_driver_with_erk_agrees_with_the_reference(rig, tight):
    _, t_pk, p_pk = tight
    res = pdbfs.sweep(rig, {"hammer.v0": [2.73]}, method="erk", backend="c")
    assert res[0]["peak_pressure"] == pytest.approx(p_pk, rel=1e-6)
    assert res[0]["time_of_peak"] == pytest.approx(t_pk, abs=1e-8)
    single = rig.simulate(backend="casadi", rtol=1e-11, atol=1e-13).summary()
    for k in ("pulse_duration", "peak_contact_force", "restitution_coefficient"):
        assert res[0][k] == pytest.approx(single[k], rel=1e-6), k
    # the default sweep is this method
    assert pdbfs.sweep(rig, {"hammer.v0": [2.73]})[0]["peak_pressure"] == pytest.approx(
        p_pk, rel=1e-7)


def test_auto_keeps_the_explicit_method_for_a_long_ringing_run():
    """the drop rig's 1.5 s are 10,000 rad of its breech mode, rung by the
    blows: every method resolves it, and the explicit method takes several
    times fewer steps than Adams (measured 12,800 against 70,700, 2x the
    time), so "auto" keeps it"""
    from pdbfs.models import drop_rig
    rig = drop_rig()
    sim = Simulator.of(rig)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    assert sim.resolve_method("auto", p, x0, 1.5, "c") == "erk"
    assert sim.resolve_method("auto", p, x0, 0.02, "c") == "erk"
    steps = {m: rig.simulate(1.5, n_out=11, method=m, backend="c").stats["steps"] for m in ("erk", "adams")}
    assert steps["adams"] > 3 * steps["erk"]