"""Campaigns against physics: with the temperature laws off every blow is
the single run and the damage N times one blow's; the heat a blow hands the
thermal network is the energy its mechanics lost; over a campaign the
dissipated heat is the stored heat and the heat lost through the boundaries
(each found its own way); one capacitor heated per blow and cooled between
blows climbs the geometric series to its steady temperature; the operator's
rule holds the peak; a schedule's blows are the single runs at its values;
several impacts per blow count each."""
import math

import numpy as np
import pytest

from pdbfs.components.thermal import FixedTemperature, HeatCapacitor, ThermalConductor
from pdbfs.errors import ParameterError
from pdbfs.fatigue import Breech
from pdbfs.models import PaperRig, paper_rig, paper_thermal_rig
from pdbfs.rig import Rig
from pdbfs.studies.campaign import HeatNetwork, HoldPeak, campaign

OFF = {"oil.alpha_T": 0.0, "seal.B": 0.0}
FIGURES = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force")
MASSES = {"hammer": 2948.4, "piston": 241.7, "breech": 500.0}
G = 9.80665
RIG = paper_thermal_rig()


def _mechanical_energy(res, i):
    """The paper rig's kinetic and spring energy at output point i (Table 1's
    stiffnesses: the oil column's law off)."""
    e = sum(0.5 * m * res[f"{n}.v"][i] ** 2 for n, m in MASSES.items())
    e += 5.958e10 * max(res["contact.d"][i], 0.0) ** 2.5 / 2.5
    e += 0.5 * 2.228e8 * max(res["oil.d"][i], 0.0) ** 2
    return e + 0.5 * 2.5e10 * res["breech.s"][i] ** 2


def test_with_the_laws_off_every_blow_is_the_single_run_and_the_damage_n_blows():
    """The temperatures climb (the heat still flows) but act on nothing: each
    blow's pulse is the single run's to 1e-9 (measured 4e-15), and the
    damage is N times one blow's."""
    n = 300
    res = campaign(RIG, n, 10.0, params=OFF, check_every=100)
    one = RIG.simulate(0.02, params=OFF)
    s = one.summary()
    t = res.table
    assert t["oil_temperature"].iloc[-1] > t["oil_temperature"].iloc[0] + 1.0
    for k in FIGURES:
        assert np.max(np.abs(t[k] / s[k] - 1)) < 1e-9, k
    d1 = Breech().peak_damage(s["peak_pressure"])
    assert res.totals["damage"] == pytest.approx(n * d1, rel=1e-9)
    assert res.life == pytest.approx(1 / d1, rel=1e-9)
    # the blows read whole: the rainflow of the single run's history
    assert list(res.checks["blow"]) == [1, 101, 201, 300]
    whole = Breech().damage(one, signal="oil.pressure")
    assert np.allclose(res.checks["damage_history"], whole, rtol=1e-9, atol=0)


def test_with_the_laws_off_through_casadi_at_a_tight_tolerance():
    """IDAS's steps move with the temperatures' size: 1e-9 needs rtol 1e-10."""
    res = campaign(RIG, 3, 10.0, params=OFF, backend="casadi", rtol=1e-10, check_every=0,
                   temperatures={"oil_heat.T": 320.0})
    s = RIG.simulate(0.02, params=OFF, backend="casadi", rtol=1e-10).summary()
    for k in ("peak_pressure", "pulse_duration"):
        assert np.max(np.abs(res.table[k] / s[k] - 1)) < 1e-9, k


def test_the_heat_a_blow_hands_over_is_what_its_mechanics_lost():
    """Laws off (the oil's spring energy is k d^2 / 2): the energy the blow's
    masses and springs lost, from its Result, is each blow's
    energy_dissipated, from the capacitors' temperatures and the boundaries'
    flows (measured 3e-10)."""
    res = campaign(RIG, 40, 10.0, params=OFF, check_every=0)
    one = RIG.simulate(0.02, n_out=4001, params=OFF, rtol=1e-10)
    lost = _mechanical_energy(one, 0) - _mechanical_energy(one, -1)
    assert lost > 1000.0
    assert np.allclose(res.table["energy_dissipated"], lost, rtol=1e-7, atol=0)


def test_over_a_campaign_the_dissipated_heat_is_stored_or_lost():
    """Laws on, the oil warming for 500 blows: the heat the blows dissipated
    (what the capacitors gained during each blow, and what left during it) is
    what the capacitors hold at the end against the start, plus what left
    through the boundaries over every pause (Van Loan's integral of the
    boundaries' conductances, not the capacitors' loss): to 1e-6 (measured 1e-12)."""
    res = campaign(RIG, 500, 10.0, check_every=0)
    o = res.totals
    C = {"oil_heat.T": 2.80e4, "piston_heat.T": 1.112e5, "breech_heat.T": 2.30e5}
    stored = sum(c * (res.final[n] - res.initial[n]) for n, c in C.items())
    assert o["heat_stored"] == pytest.approx(stored, rel=1e-12)
    assert stored > 0.3 * o["energy_dissipated"] and o["heat_lost"] > 0.1 * o["energy_dissipated"]
    assert abs(o["energy_dissipated"] - stored - o["heat_lost"]) < 1e-6 * o["energy_dissipated"]
    # each blow starts where the pause after the one before left it
    t = res.table
    assert np.all(t["oil_heat.T_end"] > t["oil_heat.T"])
    assert np.all(t["oil_heat.T"].iloc[1:].to_numpy() < t["oil_heat.T_end"].iloc[:-1].to_numpy())


def test_a_pause_is_the_network_simulated_and_its_lost_heat_the_rooms_flow():
    """The closed form of a pause against the network integrated tightly:
    the temperatures, and the heat the room took (the trapezoidal rule on a
    fine grid of the room's heat flow)."""
    net = HeatNetwork.of(RIG, {p.name: p.value for p in RIG.parameters()})
    T = np.array([310.0, 300.0, 296.0])
    pause = net.pause(900.0)
    after, lost = pause(T)
    sim = RIG.thermal_network().simulate(900.0, n_out=90001, start=dict(zip(net.states, T)),
                                         rtol=1e-12, atol=1e-12, backend="casadi")
    assert np.allclose(after, [sim[s][-1] for s in net.states], rtol=0, atol=1e-8)
    room = np.trapezoid(sim["room.port.Q_flow"], sim.t)
    assert lost == pytest.approx(room, rel=1e-8)


class OneBodyNetwork(Rig):
    """One body of 2e4 J/K losing heat to the room through 20 W/K."""

    name = "one_body_network"

    def declare(self):
        declare_one_body(self)


def declare_one_body(rig):
    rig.room = FixedTemperature(T=293.15)
    rig.body = HeatCapacitor(C=2.0e4, T0=293.15)
    rig.wall = ThermalConductor(G=20.0)
    rig.connect(rig.body.port, rig.wall.port_a)
    rig.connect(rig.wall.port_b, rig.room.port)


class OneBodyRig(PaperRig):
    """The paper rig whose contact and seal warm one body (no temperature law)."""

    name = "one_body"
    thermal_network = OneBodyNetwork

    def options(self, name):
        return {"contact": {"heat_port": True}, "seal": {"heat_port": True}}.get(name, {})

    def declare(self):
        super().declare()
        declare_one_body(self)
        self.connect(self.contact.heat_port, self.seal.heat_port, self.body.port)


@pytest.mark.parametrize("G", [20.0, 40.0])
def test_one_body_heated_per_blow_climbs_the_geometric_series(G):
    """Q per blow, e^(-S/tau) kept over each period (tau = C/G, 1000 s for the
    rig's own G, 500 s for G given in params): the rise at the k-th blow is
    (q/C)(1 - r^(k-1))/(1 - r), r = e^(-S/tau), the heat q that reaches the
    next blow between Q r (all of it at the blow's start) and Q r
    e^(t_blow/tau) (all at its end); Q from the mechanics."""
    rig = OneBodyRig()
    S, n, C, tau, t_b = 100.0, 120, 2.0e4, 2.0e4 / G, 0.02
    res = campaign(rig, n, S, check_every=0, params={"wall.G": G} if G != 20.0 else None)
    one = rig.simulate(t_b, n_out=4001, rtol=1e-10)
    Q = _mechanical_energy(one, 0) - _mechanical_energy(one, -1)
    r = math.exp(-S / tau)
    k = np.arange(1, n + 1)
    series = (1 - r ** (k - 1)) / (1 - r) / C
    rise = res.table["body.T"].to_numpy() - 293.15
    assert rise[0] == 0.0
    lo, hi = Q * r * series, Q * r * math.exp(t_b / tau) * series
    assert np.all(rise[1:] >= lo[1:] * (1 - 1e-7)) and np.all(rise[1:] <= hi[1:] * (1 + 1e-7))
    assert rise[-1] == pytest.approx(Q * r / (C * (1 - r)), rel=1e-4)    # its steady rise


def test_the_rule_holds_the_peak_in_its_band():
    """The oil warms and the peak falls by 0.6 % over 2000 blows unheld; a
    band of +-0.1 % around the first peak is held: no two blows in a row
    outside it, the hammer sped up as the oil warms."""
    free = campaign(RIG, 2000, 10.0, check_every=0)
    p0 = free.table["peak_pressure"].iloc[0]
    assert free.table["peak_pressure"].iloc[-1] < p0 * (1 - 0.005)
    held = campaign(RIG, 2000, 10.0, rule=HoldPeak(p0 * 0.999, p0 * 1.001), check_every=0)
    peaks = held.table["peak_pressure"].to_numpy()
    out = (peaks < p0 * 0.999) | (peaks > p0 * 1.001)
    assert out.sum() > 0 and not np.any(out[1:] & out[:-1])
    v0 = held.table["hammer.v0"].to_numpy()
    assert v0[0] == 2.73 and v0[-1] > 2.73
    # a corrected blow lands near the band's middle (the peak grows almost as v0)
    after = np.flatnonzero(out[:-1]) + 1
    assert np.all(np.abs(peaks[after] / p0 - 1) < 2e-4)
    assert held.band == (p0 * 0.999, p0 * 1.001)


def test_a_schedules_blows_are_the_single_runs_at_its_values():
    """v0 per blow from a schedule, drop heights converted to v0 = sqrt(2 g h)."""
    v = np.array([2.5, 2.73, 3.0] * 4)
    res = campaign(paper_rig(), 12, 5.0, schedule={"hammer.v0": v}, check_every=0)
    for i in (0, 1, 2):
        s = paper_rig().simulate(0.02, params={"hammer.v0": v[i]}).summary()
        assert np.allclose(res.table["peak_pressure"].iloc[i::3], s["peak_pressure"], rtol=1e-9)
    h = np.array([0.3, 0.4, 0.5])
    res = campaign(paper_rig(), 3, 5.0, schedule={"drop_height": h}, check_every=0)
    assert np.allclose(res.table["hammer.v0"], np.sqrt(2 * G * h), rtol=1e-15)


def test_a_blow_of_several_impacts_counts_each():
    """The drop rig's hammer strikes again: a blow's damage is every impact's
    cycle from the rest pressure (the piston's weight on the oil) to its
    peak, near its history's rainflow (whose ripples add a little)."""
    from pdbfs.models import drop_rig
    rig = drop_rig()
    res = campaign(rig, 2, 30.0, check_every=0)
    one = rig.simulate(1.5)
    peaks, rest = one.summary()["impact_peak_pressures"], one["oil.pressure"][0]
    assert len(peaks) > 1 and rest > 0
    d = float(np.sum(Breech().peak_damage(peaks, rest)))
    assert np.allclose(res.damages, d, rtol=1e-9)
    assert d > Breech().peak_damage(peaks[0]) * 1.01
    whole = Breech().damage(rig.simulate(1.5, n_out=30001), signal="oil.pressure")
    assert d == pytest.approx(whole, rel=0.01) and d < whole


def test_the_examples_in_the_docstrings_run():
    import doctest

    from pdbfs.studies.campaign import plan, run
    for mod in (plan, run):
        failed, tried = doctest.testmod(mod)
        assert tried and not failed, mod.__name__


def test_a_run_goes_on_from_where_the_result_ends_and_progress_is_told():
    """Result.final, the states at the end: a run of 10 ms from the end of a
    run of 10 ms is the run of 20 ms there (to its tolerance)."""
    rig = paper_rig()
    first = rig.simulate(0.01, rtol=1e-10)
    assert first.final == {s: first[s][-1] for s in rig.compile().x_names}
    on = rig.simulate(0.01, start=first.final, rtol=1e-10)
    whole = rig.simulate(0.02, n_out=3, rtol=1e-10)
    for s in ("hammer.s", "hammer.v", "piston.v"):
        assert on.final[s] == pytest.approx(whole.final[s], rel=1e-7, abs=1e-9)
    told = []
    campaign(RIG, 450, 10.0, check_every=0, progress=lambda done, total: told.append((done, total)))
    assert told == [(200, 450), (400, 450), (450, 450)]


@pytest.mark.parametrize("kwargs,culprit", [
    ({"blows": 0}, "blows"), ({"blows": True}, "blows"), ({"blows": 2.5}, "blows"),
    ({"period": -1.0}, "period"), ({"period": 0.0}, "period"), ({"period": math.nan}, "period"),
    ({"period": math.inf}, "period"), ({"period": 0.02}, "period"),
    ({"t_blow": -0.02}, "t_blow"),
    ({"schedule": {"hammer.v0": [2.7, 2.8]}}, "2 values for a campaign of 5"),
    ({"schedule": {"hammer.v0": [2.7] * 5}, "params": {"hammer.v0": 2.7}}, "params and in the"),
    ({"schedule": {"hammer.v0": [2.7] * 4 + [math.nan]}}, "finite"),
    ({"schedule": {"drop_height": [0.3] * 5, "hammer.v0": [2.7] * 5}}, "twice"),
    ({"schedule": {"room.T": [300.0] * 5}}, "thermal network"),
    ({"schedule": {"oil_heat.T0": [300.0] * 5}}, "start temperature"),
    ({"rule": "hold:1:2"}, "unknown rule"), ({"rule": 3}, "rule must be"),
    ({"rule": "hold-peak:9e7:9.2e7", "schedule": {"hammer.v0": [2.7] * 5}}, "schedule sets"),
    ({"temperatures": {"oil.T": 300.0}}, "oil.T"),
    ({"temperatures": {"oil_heat.T": 0.0}}, "positive"),
    ({"temperatures": {"oil_heat.T": 300.0}, "params": {"oil_heat.T0": 300.0}}, "give it once"),
    ({"oil": "piston.T"}, "oil"),
    ({"damage": "rainflow"}, "damage"), ({"check_every": -1}, "check_every"),
    ({"chunk_size": 0}, "chunk_size"), ({"params": {"oil.kk": 1.0}}, "oil.kk"),
    ({"breech": "big"}, "Breech"),
])
def test_bad_arguments_are_refused_in_one_line_before_any_blow(kwargs, culprit, tmp_path):
    args = {"blows": 5, "period": 10.0, **kwargs}
    with pytest.raises(ParameterError) as err:
        campaign(RIG, args.pop("blows"), args.pop("period"), out=tmp_path / "o", **args)
    assert culprit in str(err.value) and "\n" not in str(err.value)
    assert not (tmp_path / "o").exists()


def test_a_rig_without_heat_refuses_temperatures_and_a_rule_its_unknown_setting():
    with pytest.raises(ParameterError, match="no thermal network"):
        campaign(paper_rig(), 5, 10.0, temperatures={"oil_heat.T": 300.0})
    with pytest.raises(ParameterError, match="no thermal network"):
        campaign(paper_rig(), 5, 10.0, oil="oil_heat.T")
    with pytest.raises(ParameterError, match="hammer.vv' before blow 2"):
        campaign(paper_rig(), 5, 10.0, rule=lambda blows: {"hammer.vv": 1.0})
    with pytest.raises(ParameterError, match="before blow 2: not a finite"):
        campaign(paper_rig(), 5, 10.0, rule=lambda blows: {"hammer.v0": math.nan})
