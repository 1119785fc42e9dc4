"""pdbfs.fatigue against closed forms and independent references: rainflow
against ASTM E1049-85's worked example and fatpack's counter, Miner and
Paris lives against their closed forms, Lamé against the wall's equilibrium,
a rig's damage against its output grid and its summary."""
import doctest
import importlib
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.fatigue import (GUN_STEEL_PARIS, Breech, ParisLaw, SNCurve, ThickCylinder,
                           campaign_life, crack_growth_cycles, equivalent_range, history_values,
                           rainflow)
from pdbfs.models import paper_rig


# -- rainflow --------------------------------------------------------------------------
def test_rainflow_is_astm_e1049s_worked_example():
    """ASTM E1049-85, section 5.4.4 (its Fig. 6): ranges and counts, in its order."""
    cycles = rainflow([-2, 1, -3, 5, -1, 3, -4, 4, -2])
    assert list(cycles.columns) == ["range", "mean", "count"]
    assert cycles["range"].tolist() == [3, 4, 4, 8, 9, 8, 6]
    assert cycles["count"].tolist() == [0.5, 0.5, 1, 0.5, 0.5, 0.5, 0.5]
    assert cycles["mean"].tolist() == [-0.5, -1, 1, 1, 0.5, 0, 1]


def _reversals(y):
    d = np.diff(y)
    k = np.flatnonzero(d[:-1] * d[1:] < 0) + 1
    return np.concatenate([[y[0]], y[k], [y[-1]]])


@pytest.mark.parametrize("seed", range(6))
def test_rainflow_agrees_with_fatpacks_counter_on_random_histories(seed):
    """fatpack's four-point counter closes the same cycles (range and mean) and
    leaves as its residue the half cycles ASTM's three-point method counts."""
    fatpack = pytest.importorskip("fatpack")
    rng = np.random.default_rng(seed)
    y = rng.normal(size=int(rng.integers(50, 4000))) * 1e6 + rng.normal() * 1e6
    closed, residue = fatpack.find_rainflow_cycles(_reversals(y))
    got = rainflow(y)
    full = got[got["count"] == 1.0]
    half = got[got["count"] == 0.5]
    assert len(full) + len(half) == len(got) and len(full) == len(closed) > 0
    np.testing.assert_allclose(np.sort(full["range"]), np.sort(np.abs(closed[:, 0] - closed[:, 1])),
                               rtol=1e-14)
    np.testing.assert_allclose(np.sort(full["mean"]), np.sort(closed.mean(axis=1)), rtol=1e-12)
    np.testing.assert_allclose(np.sort(half["range"]), np.sort(np.abs(np.diff(residue))), rtol=1e-14)


def test_a_history_may_be_a_pair_or_a_trace_and_bad_values_are_refused():
    t = np.linspace(0, 1, 9)
    y = np.array([-2, 1, -3, 5, -1, 3, -4, 4, -2], dtype=float)
    from pdbfs.studies import Trace
    trace = Trace(t, y)
    for history in ((t, y), trace, list(y)):
        np.testing.assert_array_equal(history_values(history), y)
    with pytest.raises(pdbfs.DataError, match="value 2 is nan"):
        rainflow([0.0, 1.0, float("nan"), 2.0])
    with pytest.raises(pdbfs.DataError, match="9 times but 3 values"):
        rainflow((t, y[:3]))
    assert len(rainflow([1.0])) == 0 and len(rainflow([])) == 0


# -- S-N and Miner ---------------------------------------------------------------------
def test_miners_damage_of_constant_amplitude_is_its_closed_form():
    """n cycles from 0 to P: D = n (k P / S_ref)^m / N_ref, k Lamé's bore factor."""
    curve = SNCurve(m=4.2, stress_range_ref=300e6, cycles_ref=2e5)
    breech = Breech(ThickCylinder(0.05, 0.12), curve)
    n, p = 40, 150e6
    history = np.zeros(2 * n + 1)                   # 0, P, 0, ..., P, 0: n blows
    history[1::2] = p
    k = (0.12 ** 2 + 0.05 ** 2) / (0.12 ** 2 - 0.05 ** 2)
    exact = n * (k * p / 300e6) ** 4.2 / 2e5
    assert breech.damage(history) == pytest.approx(exact, rel=1e-12)
    assert breech.peak_damage(p) * n == pytest.approx(exact, rel=1e-12)
    assert campaign_life([breech.peak_damage(p)]) == pytest.approx(1 / breech.peak_damage(p),
                                                                   rel=1e-12)


def test_ranges_at_or_below_the_endurance_limit_do_no_damage():
    curve = SNCurve(3.0, 200e6, 1e6, endurance_limit=50e6)
    cycles = {"range": [50e6, 49e6, 0.0], "count": [1.0, 1.0, 0.5]}
    assert curve.damage(cycles) == 0.0
    assert curve.damage({"range": [50.001e6], "count": [1.0]}) == pytest.approx(
        (50.001 / 200) ** 3 / 1e6, rel=1e-12)
    assert np.isinf(curve.cycles_to_failure([50e6, 10e6])).all()


@pytest.mark.parametrize("args, culprit", [((0.0, 1e8, 1e6), "m = 0 must be positive"),
                                           ((-3.0, 1e8, 1e6), "m = -3 must be positive"),
                                           ((3.0, -1e8, 1e6), "stress_range_ref"),
                                           ((3.0, 1e8, 0.0), "cycles_ref = 0"),
                                           ((3.0, 1e8, 1e6, -1.0), "endurance_limit"),
                                           ((float("nan"), 1e8, 1e6), "m = nan")])
def test_a_bad_sn_curve_is_one_line_naming_its_number(args, culprit):
    with pytest.raises(pdbfs.ParameterError) as err:
        SNCurve(*args)
    assert culprit in str(err.value) and "\n" not in str(err.value)


# -- Lamé -------------------------------------------------------------------------------
def test_lame_hoop_stress_balances_the_pressure_and_has_the_thin_wall_limit():
    """Half the wall carries the pressure on the bore: integral of the hoop
    stress over the wall = p a; a thin wall carries p a / t."""
    from scipy.integrate import quad
    cyl = ThickCylinder(0.08, 0.2)
    p = 250e6
    carried, _ = quad(lambda r: cyl.hoop_stress(p, r), 0.08, 0.2, epsrel=1e-12)
    assert carried == pytest.approx(p * 0.08, rel=1e-10)
    assert cyl.bore_hoop_stress(p) == pytest.approx(cyl.hoop_stress(p, 0.08), rel=1e-14)
    thin = ThickCylinder(1.0, 1.001)
    assert thin.bore_hoop_stress(p) == pytest.approx(p * 1.0 / 0.001, rel=1.1e-3)
    with pytest.raises(pdbfs.ParameterError, match="outer_radius = 0.05 m must be above"):
        ThickCylinder(0.08, 0.05)


# -- Paris' law ------------------------------------------------------------------------
@pytest.mark.parametrize("m", [2.0, 3.0, 4.5])
@pytest.mark.parametrize("faces", [True, False])
def test_paris_life_of_constant_amplitude_is_its_closed_form(m, faces):
    cyl, dp, a0, af, Y = ThickCylinder(0.06, 0.15), 120e6, 0.3e-3, 0.03, 1.12
    law = ParisLaw(C=1e-11 * 1e-6 ** m, m=m)
    ds = dp * ((0.15 ** 2 + 0.06 ** 2) / (0.15 ** 2 - 0.06 ** 2) + (1.0 if faces else 0.0))
    base = law.C * (Y * ds * math.sqrt(math.pi)) ** m
    exact = (math.log(af / a0) / base if m == 2.0 else
             (a0 ** (1 - m / 2) - af ** (1 - m / 2)) / ((m / 2 - 1) * base))
    got = crack_growth_cycles(cyl, law, dp, a0, af, Y=Y, crack_face_pressure=faces)
    assert got == pytest.approx(exact, rel=1e-9)
    assert crack_growth_cycles(cyl, law, dp, a0, af, Y=lambda r: Y,
                               crack_face_pressure=faces) == pytest.approx(exact, rel=1e-9)


def test_paris_life_with_a_geometry_function_matches_an_ode_integration():
    """Y(a/W) growing through the wall: against the crack's depth integrated
    in cycles by scipy's solve_ivp to the final depth (an event)."""
    from scipy.integrate import solve_ivp
    cyl, law, dp, a0, af = ThickCylinder(0.08, 0.16), GUN_STEEL_PARIS, 90e6, 0.5e-3, 0.04
    Y = lambda r: 1.12 + 0.6 * r + 2.0 * r ** 2       # noqa: E731
    ds = cyl.bore_hoop_stress(dp) + dp
    rate = lambda n, a: [law.C * (Y(a[0] / 0.08) * ds * math.sqrt(math.pi * a[0])) ** law.m]  # noqa: E731
    reached = lambda n, a: a[0] - af                 # noqa: E731
    reached.terminal = True
    sol = solve_ivp(rate, (0, 1e9), [a0], events=reached, rtol=1e-12, atol=1e-15, method="DOP853")
    assert crack_growth_cycles(cyl, law, dp, a0, af, Y=Y) == pytest.approx(sol.t_events[0][0],
                                                                          rel=1e-8)


def test_a_campaign_grows_a_crack_as_its_equivalent_range_does():
    """Blocks of mixed ranges: the blocks from a0 to af integrated cycle by
    cycle (the depth growing per block by every range's increment) equal the
    equivalent range's cycles over the block's count."""
    from scipy.integrate import solve_ivp
    cyl, law, a0, af = ThickCylinder(0.08, 0.16), GUN_STEEL_PARIS, 0.5e-3, 0.02
    block = {"range": [60e6, 90e6, 120e6], "count": [5.0, 2.0, 1.0]}
    k = cyl.bore_factor + 1.0
    per_block = lambda n, a: [sum(c * law.C * (1.12 * k * r * math.sqrt(math.pi * a[0])) ** law.m  # noqa: E731
                                  for r, c in zip(block["range"], block["count"]))]
    reached = lambda n, a: a[0] - af                 # noqa: E731
    reached.terminal = True
    sol = solve_ivp(per_block, (0, 1e9), [a0], events=reached, rtol=1e-12, atol=1e-15)
    eq = equivalent_range(block, law.m)
    blocks = crack_growth_cycles(cyl, law, eq, a0, af) / sum(block["count"])
    assert blocks == pytest.approx(sol.t_events[0][0], rel=1e-8)


@pytest.mark.parametrize("kw, culprit", [({"a0": 0.0}, "a0 = 0 must be positive"),
                                         ({"af": 0.1}, "af = 0.1 m"),
                                         ({"a0": 0.03, "af": 0.02}, "0 < a0 < af"),
                                         ({"Y": -1.0}, "Y = -1 must be positive"),
                                         ({"Y": lambda r: 1.0 - 20 * r}, "Y(a / W) = "),
                                         ({"pressure_range": -1e6}, "pressure_range")])
def test_bad_crack_growth_input_is_one_line(kw, culprit):
    args = {"pressure_range": 1e8, "a0": 1e-3, "af": 0.02, **kw}
    with pytest.raises(pdbfs.ParameterError) as err:
        crack_growth_cycles(ThickCylinder(0.08, 0.16), GUN_STEEL_PARIS, **args)
    assert culprit in str(err.value) and "\n" not in str(err.value)


# -- blows and campaigns ---------------------------------------------------------------
def _blow(peak, ripple, rng):
    """A blow from rest with a ripple on its pulse, back to rest."""
    s = np.linspace(0, 1, 400)
    return peak * np.sin(np.pi * s) ** 2 * (1 + ripple * np.sin(40 * s + rng.uniform(0, 6)))


def test_a_campaigns_damage_is_the_sum_of_its_blows():
    """Blows that start and end at rest close their cycles with themselves:
    the rainflow of the whole campaign's history does what its blows do."""
    rng = np.random.default_rng(3)
    blows = [_blow(rng.uniform(50e6, 200e6), rng.uniform(0, 0.1), rng) for _ in range(30)]
    breech = Breech()
    each = [breech.damage(b) for b in blows]
    assert breech.damage(np.concatenate(blows)) == pytest.approx(sum(each), rel=1e-12)
    # the life: blow by blow, the campaign repeated, until Miner's sum reaches 1
    life = campaign_life(each)
    whole = math.floor(1 / sum(each))
    left, k = 1 - whole * sum(each), 0
    while left > each[k]:
        left -= each[k]
        k += 1
    assert life == pytest.approx(whole * len(each) + k + left / each[k], rel=1e-12)


def test_a_rigs_blow_damage_is_located_on_the_solution_not_the_grid():
    """The reversals of the paper rig's pressure are located on its solution:
    the damage is the same on a coarse and a fine output grid, its highest
    reversal is the summary's peak, and the ripples add a little to the
    one cycle the summary's peak gives."""
    breech, rig = Breech(), paper_rig()
    coarse = rig.simulate(0.02, n_out=161, params={"hammer.v0": 3.5})
    fine = rig.simulate(0.02, n_out=8001, params={"hammer.v0": 3.5})
    d_coarse, d_fine = breech.damage(coarse), breech.damage(fine)
    assert d_coarse == pytest.approx(d_fine, rel=1e-7)
    peak = fine.summary()["peak_pressure"]
    assert history_values(coarse).max() == pytest.approx(peak, rel=1e-9)
    assert 1.0 < d_fine / breech.peak_damage(peak) < 1.01


def test_a_blow_cut_off_by_the_horizon_is_refused():
    res = paper_rig().simulate(0.004, n_out=401)
    with pytest.raises(pdbfs.DataError, match="still running at t_end = 0.004 s"):
        Breech().damage(res)


def test_a_result_with_several_pressures_needs_the_one_named():
    from pdbfs.models import RIGS
    res = RIGS["paper-hydraulic"]().simulate(0.02, n_out=401)
    with pytest.raises(pdbfs.ParameterError, match="variables in Pa"):
        rainflow(res)
    assert Breech().damage(res, signal="oil.p") > 0


# -- the examples in the docstrings run --------------------------------------------------
@pytest.mark.parametrize("module", ["counting", "sn", "cylinder", "crack", "breech"])
def test_the_docstring_examples_run(module):
    mod = importlib.import_module(f"pdbfs.fatigue.{module}")
    failed, tried = doctest.testmod(mod, optionflags=doctest.ELLIPSIS)
    assert tried > 0 and failed == 0


def test_the_default_sn_curve_is_the_paris_life_of_a_half_millimetre_flaw():
    """As its description says: the default breech's S-N life is 5 % short of
    the Paris-law life of a 0.5 mm flaw growing to 20 mm, at any pressure range."""
    from pdbfs.fatigue import BREECH_CYLINDER, GUN_STEEL_SN
    for dp in (50e6, 150e6):
        sn = GUN_STEEL_SN.cycles_to_failure(BREECH_CYLINDER.bore_hoop_stress(dp))
        paris = crack_growth_cycles(BREECH_CYLINDER, GUN_STEEL_PARIS, dp, 0.5e-3, 0.02)
        assert 0.94 < sn / paris < 0.96
