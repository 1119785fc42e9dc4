"""Initialization: free starts and initial equations solved before
integration (Newton, exact Jacobian), checked against statics by hand; a
start at rest stays at rest on both back ends; systems with no solution or
a singular one are refused naming their equations."""
import json
import subprocess
import sys

import numpy as np
import pytest

from pdbfs.components import Fixed, Force, Mass, Spring
from pdbfs.errors import ModelError, ParameterError
from pdbfs.models import drop_rig, hydraulic_pulse_rig, paper_rig
from pdbfs.modelling import eq
from pdbfs.rig import Rig
from hardening import Hardening

TIGHT = dict(rtol=1e-10, atol=1e-12)


def statics(rig, params=None):
    """The stack resting under gravity, by hand: each contact, oil column and
    mount carries the weight above it (linear oil and mount, Hertz contact).
    Positions are positive down. The mount (breech to frame) is unstretched
    at breech.s = frame.s0 - mount.s_rel0 (its stretch is frame.s0 - breech.s
    - s_rel0) and compressed by the weight; the contact's indentation is
    hammer.s - piston.s - gap, so the hammer sinks by (m g / k)^(1/n) below
    piston.s + gap."""
    P = {p.name: p.value for p in rig.compile().params}
    P.update(params or {})
    g = P["g"]
    mh, mp, mb = P["hammer.m"], P["piston.m"], P["breech.m"]
    breech = P["frame.s0"] - P["mount.s_rel0"] + (mh + mp + mb) * g / P["mount.k"]
    piston = breech + (mh + mp) * g / P["oil.k"]
    sink = (mh * g / P["contact.k"]) ** (1.0 / P["contact.n"])
    return {"breech.s": breech, "piston.s": piston,
            "hammer.s": piston + P["contact.gap"] + sink}


def test_hammer_resting_on_the_piston_starts_where_statics_puts_it():
    rig = drop_rig(rest=True)
    P = {p.name: p.value for p in rig.compile().params}
    assert P["oil.n"] == 1.0 and P["mount.n"] == 1.0 and P["contact.n"] == 1.5
    res = rig.simulate(0.001, n_out=3, **TIGHT)
    init = res.initial
    assert set(init.solved) == set(rig.compile().x_names)
    for name, value in statics(rig).items():
        assert init[name] == pytest.approx(value, rel=1e-10), name
        assert res[name][0] == init[name]
    for body in ("hammer", "piston", "breech"):
        assert init[f"{body}.v"] == 0.0 or abs(init[f"{body}.v"]) < 1e-15
    # the residuals vanish: every acceleration is zero at the solved start
    dae = rig.compile()
    x0 = np.array([init[n] for n in dae.x_names])
    acc = np.asarray(dae.function("ode")(0.0, x0, [], dae.p_default())).ravel()
    assert np.max(np.abs(acc)) < 1e-9 * P["g"]
    assert max(init.residuals.values()) < 1e-12
    # the contact carries exactly the hammer's weight
    assert res["contact.fc"][0] == pytest.approx(P["hammer.m"] * P["g"], rel=1e-10)


@pytest.mark.parametrize("backend", ["casadi", "c"])
def test_a_start_at_rest_stays_at_rest(backend):
    rig = drop_rig(rest=True)
    # CVODE's Adams on both backends (the compiled backend's explicit method lets a
    # resting body drift by up to 6e-8 m/s over this run: not a test of the start)
    res = rig.simulate(0.05, n_out=101, backend=backend, rtol=1e-8, atol=1e-10, method="adams")
    for body in ("hammer", "piston", "breech"):
        assert np.max(np.abs(res[f"{body}.v"])) < 1e-9
        assert np.ptp(res[f"{body}.s"]) < 1e-12
    assert np.ptp(res["contact.fc"]) < 1e-6 * res["contact.fc"][0]


def test_steady_option_solves_the_same_start_as_the_rigs_initial_equations():
    # the paper rig without gravity started "steady": the hammer, touching
    # the piston at the start, rests anywhere above it: refused naming its
    # equation and its position
    with pytest.raises(ModelError, match=r"not determined.*der\(hammer\.v\) = 0.*hammer\.s"):
        paper_rig().simulate(0.001, n_out=3, initial="steady")
    # the drop rig (released from h) started "steady": at rest, the hammer lies
    # on the piston (its guess, h above it, is outside the contact)
    res = drop_rig().simulate(0.001, n_out=3, initial="steady")
    for name, value in statics(drop_rig()).items():
        assert res.initial[name] == pytest.approx(value, rel=1e-10), name
    # the rest rig's start solved by its own equations or by initial="steady"
    a = drop_rig(rest=True).simulate(0.001, n_out=3).initial
    b = drop_rig(rest=True).simulate(0.001, n_out=3, initial="steady").initial
    for n in a.values:
        assert b[n] == pytest.approx(a[n], rel=1e-12, abs=1e-18)
    # only the piston and the breech at rest, the hammer where it is declared
    r = drop_rig().simulate(0.001, n_out=3, initial=["piston.s", "piston.v", "breech.s",
                                                     "breech.v"])
    assert r.initial.solved == ["piston.s", "piston.v", "breech.s", "breech.v"]
    assert r.initial["hammer.s"] == drop_rig().simulate(0.001, n_out=3)["hammer.s"][0]


class Preloaded(Rig):
    """A mass held by a spring to the frame, with a constant load; the spring
    starts at a given preload, solved for the mass's position."""

    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=2e6)
        self.mass = Mass(m=3.0, s0=0.0)
        self.load = Force(F=100.0)
        self.connect(self.frame.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)
        self.connect(self.load.flange, self.mass.flange_b)
        self.mass.free("s")

    def initial_equations(self):
        return [eq(self.spring.f, self.preload)]

    preload = 250.0


def test_a_spring_at_its_preload():
    res = Preloaded().simulate(0.01, n_out=11, **TIGHT)
    assert res.initial.solved == ["mass.s"]
    assert res["spring.f"][0] == pytest.approx(250.0, rel=1e-12)
    assert abs(res.initial["mass.s"]) == pytest.approx(250.0 / 2e6, rel=1e-12)


class NoSolution(Preloaded):
    def initial_equations(self):
        return [eq(self.mass.s ** 2, -1e-6)]      # s^2 = -1e-6: no real solution


class TooMany(Preloaded):
    def initial_equations(self):
        return [eq(self.spring.f, 1.0), eq(self.mass.v, 0.0)]


def test_a_start_without_solution_is_refused_naming_its_equations():
    with pytest.raises(ModelError) as err:
        NoSolution().simulate(0.01)
    msg = str(err.value)
    assert "initial equation 1" in msg and "mass.s" in msg and "\n" not in msg
    with pytest.raises(ModelError, match=r"2 equations .* for 1 unknowns \(mass\.s\)"):
        TooMany().simulate(0.01)


def test_bad_initial_argument_is_refused():
    with pytest.raises(ParameterError, match="not a state"):
        paper_rig().simulate(0.001, initial=["hammer.x"])
    with pytest.raises(ParameterError, match="steady"):
        paper_rig().simulate(0.001, initial="rest")


@pytest.mark.parametrize("supply", ["accumulator", "pressure"])
def test_hydraulic_line_starts_at_the_supply_pressure_on_both_back_ends(supply):
    rig = hydraulic_pulse_rig(line=True, supply=supply)
    a = rig.simulate(0.02, **TIGHT)
    b = rig.simulate(0.02, backend="c", **TIGHT)
    p_supply = a["supply.port.p"][0]
    assert p_supply == pytest.approx(200e6 if supply == "accumulator" else 175e6, rel=1e-12)
    assert a.initial.solved == ["line.p_law"]
    assert a["line.p"][0] == pytest.approx(p_supply, rel=1e-12)
    assert abs(a["hose.q"][0]) < 1e-15
    assert b["line.p"][0] == a["line.p"][0]
    peak = np.max(a["chamber.p"])
    assert np.max(np.abs(a["chamber.p"] - b["chamber.p"])) < 1e-7 * peak
    # solved, not declared: the line's declared start (a guess) is the atmosphere
    guess = dict(zip(rig.compile().x_names, np.asarray(
        rig.compile().function("start")(rig.compile().p_default())).ravel()))
    assert guess["line.p_law"] == pytest.approx(101325.0)


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_cli_reports_the_solved_start_and_refuses_an_undetermined_one(tmp_path):
    r = cli("simulate", "--rig", "drop-rest", "--t-end", "0.002", "--n-out", "21", "--json",
            "--out", str(tmp_path / "o"), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    hand = statics(drop_rig(rest=True))
    assert data["initial"]["values"]["hammer.s"] == pytest.approx(hand["hammer.s"], rel=1e-10)
    assert data["initial"]["max_residual"] < 1e-12
    r = cli("simulate", "--rig", "paper", "--initial", "steady", "--out", str(tmp_path / "p"),
            cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "der(hammer.v) = 0" in r.stderr
    assert "Traceback" not in r.stderr and not (tmp_path / "p").exists()


def test_sweeps_start_each_point_from_its_solved_start():
    import pdbfs
    rig = hydraulic_pulse_rig(line=True)
    sw = pdbfs.sweep(rig, {"supply.p0": [150e6, 200e6]}, t_end=0.02, n_out=401, backend="c")
    got = sw.to_pandas()["peak_pressure"].to_numpy()
    for p0, peak in zip((150e6, 200e6), got):
        want = rig.simulate(0.02, n_out=401, params={"supply.p0": p0}).summary()
        assert peak == pytest.approx(want["peak_pressure"], rel=1e-6)
    assert got[1] > got[0] * 1.1     # the line's pressure follows the supply's


def test_paths_that_cannot_solve_the_start_refuse_it():
    from pdbfs.simulation import trajectory_function
    with pytest.raises(ParameterError, match="solved at initialization"):
        trajectory_function(drop_rig(rest=True), ["contact.fc"], 0.001, 11, inputs=["g"])


class Hanging(Rig):
    """frame - two hardening springs in series (the node between them an
    algebraic variable) - a body pulled by a force."""

    def declare(self):
        self.frame = Fixed()
        self.a = Hardening(k=3000.0, b=5e4)
        self.b = Hardening(k=6000.0, b=5e4)
        self.body = Mass(m=2.0, v0=1.0, s0=0.0)
        self.load = Force(F=400.0)
        self.connect(self.frame.flange, self.a.flange_a)
        self.connect(self.a.flange_b, self.b.flange_a)
        self.connect(self.b.flange_b, self.body.flange_a)
        self.connect(self.load.flange, self.body.flange_b)


def test_steady_start_of_a_rig_with_algebraic_variables():
    from scipy.optimize import brentq
    rig = Hanging()
    assert not rig.compile().is_ode
    res = rig.simulate(0.05, n_out=51, initial="steady", **TIGHT)
    stretch = [brentq(lambda s, k=k: k * (s + 5e4 * s ** 3) - 400.0, 0.0, 1.0, xtol=1e-15)
               for k in (3000.0, 6000.0)]
    assert res.initial["body.s"] == pytest.approx(sum(stretch), rel=1e-10)
    assert res.initial["body.v"] == 0.0 or abs(res.initial["body.v"]) < 1e-15
    assert "algebraic equation 1" in res.initial.equations
    assert np.max(np.abs(res["body.v"])) < 1e-9 and np.ptp(res["body.s"]) < 1e-12


class Charged(Rig):
    """An accumulator behind a hose on a sealed line at 80 MPa: in equilibrium
    with the line at the start."""

    def declare(self):
        from pdbfs.components.hydraulic import Accumulator, Orifice, Volume
        self.acc = Accumulator(V0=4e-3, p_pre=60e6 / 4, p0=200e6, n=1.4, steady_start=True)
        self.hose = Orifice(Cd=0.7, A=2e-4, dp_t=1e5)
        self.line = Volume(V=0.5e-3, K=1.5e9, p0=80e6)
        self.connect(self.acc.port, self.hose.port_a)
        self.connect(self.hose.port_b, self.line.port)


def test_an_accumulator_in_equilibrium_with_its_line():
    res = Charged().simulate(0.01, n_out=11, **TIGHT)
    assert res.initial.solved == ["acc.V_oil"]
    # the gas law at the line's pressure: V_oil = V0 (1 - (p_pre / p)^(1/n))
    want = 4e-3 * (1 - (15e6 / 80e6) ** (1 / 1.4))
    assert res.initial["acc.V_oil"] == pytest.approx(want, rel=1e-10)
    assert res["acc.p"][0] == pytest.approx(80e6, rel=1e-10)
    # nothing flows: the line stays at its pressure
    assert np.ptp(res["line.p"]) < 1e-6 * 80e6
