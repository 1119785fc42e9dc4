"""Starts whose guess lies on the slack side of a one-sided law (an oil
column exactly at zero compression, a hammer outside the contact it rests
on): solved where the equilibrium is unique, against statics by hand;
refused, saying why, where there is none or more than one; and ``initial``
lists that cannot fix their states say which states would."""
import json
import subprocess
import sys

import numpy as np
import pytest

from pdbfs.components import Fixed, Gravity, Mass, OilColumn, Spring
from pdbfs.errors import ModelError
from pdbfs.models import drop_rig, paper_rig
from pdbfs.rig import Rig

G = 9.80665


class OnOil(Rig):
    """A mass resting under gravity on an oil column (compression only)
    over the frame; its start (s = 0) is where the column just touches."""

    def declare(self):
        self.frame = Fixed()
        self.mass = Mass(m=120.0)
        self.weight = Gravity(m=self.mass.m)
        self.oil = OilColumn(k=2e8, n=1.0)
        self.connect(self.weight.flange, self.mass.flange_a)
        self.connect(self.mass.flange_b, self.oil.flange_a)
        self.connect(self.oil.flange_b, self.frame.flange)


class OnSpring(Rig):
    """The same with a compression-only spring, its start 2 mm above it."""

    def declare(self):
        self.frame = Fixed()
        self.mass = Mass(m=3.0, s0=-2e-3)
        self.weight = Gravity(m=self.mass.m)
        self.spring = Spring(k=5e5, compression_only=True)
        self.connect(self.weight.flange, self.mass.flange_a)
        self.connect(self.mass.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.frame.flange)


@pytest.mark.parametrize("n", [1.0, 1.5])
def test_a_mass_resting_on_an_oil_column_is_linearized_where_statics_puts_it(n):
    m, k = 120.0, 2e8
    lin = OnOil().linearize("steady", params={"oil.n": n})
    sink = (m * G / k) ** (1 / n)                    # k d^n = m g
    assert lin.point["mass.s"] == pytest.approx(sink, rel=1e-10)
    assert abs(lin.point["mass.v"]) < 1e-15
    (mode,) = lin.modes()
    stiffness = n * k * sink ** (n - 1)              # the column's slope there
    assert mode.omega == pytest.approx(np.sqrt(stiffness / m), rel=1e-8)


def test_a_mass_above_a_compression_only_spring_comes_to_rest_on_it():
    res = OnSpring().simulate(0.01, n_out=11, initial="steady", rtol=1e-10, atol=1e-12)
    assert res.initial["mass.s"] == pytest.approx(3.0 * G / 5e5, rel=1e-10)
    assert np.ptp(res["mass.s"]) < 1e-12


def statics(P):
    """The stack at rest, by hand (linear oil and mount, Hertz contact)."""
    mh, mp, mb, g = P["hammer.m"], P["piston.m"], P["breech.m"], P["g"]
    breech = (mh + mp + mb) * g / P["mount.k"] + P["mount.s_rel0"] + P["frame.s0"]
    piston = breech + (mh + mp) * g / P["oil.k"]
    indentation = (mh * g / P["contact.k"]) ** (1.0 / P["contact.n"])
    return breech, piston, indentation


@pytest.mark.parametrize("gap", [0.0, 2e-5, 5e-5, 1e-4, 1e-3, 0.02, -1e-3])
def test_drop_rest_with_a_gap_rests_on_the_contact(gap):
    """The contact closes at hammer.s = piston.s + gap and carries the
    hammer's weight with the indentation (m g / k)^(1/n): checked on the
    solved start itself, whatever guess the rig binds for the hammer."""
    rig = drop_rig(rest=True)
    dae = rig.compile()
    P = {p.name: p.value for p in dae.params}
    P["contact.gap"] = gap
    res = rig.simulate(0.001, n_out=3, params={"contact.gap": gap}, rtol=1e-10, atol=1e-12)
    init = res.initial
    breech, piston, indentation = statics(P)
    assert init["breech.s"] == pytest.approx(breech, rel=1e-10)
    assert init["piston.s"] == pytest.approx(piston, rel=1e-10)
    assert init["hammer.s"] - init["piston.s"] - gap == pytest.approx(indentation, rel=1e-8)
    assert res["contact.d"][0] == pytest.approx(indentation, rel=1e-8)
    assert res["contact.fc"][0] == pytest.approx(P["hammer.m"] * P["g"], rel=1e-10)
    x0 = np.array([init[n] for n in dae.x_names])
    p = np.array([P[n] for n in dae.p_names])
    acc = np.asarray(dae.function("ode")(0.0, x0, [], p)).ravel()
    assert np.max(np.abs(acc)) < 1e-9 * P["g"]


class Falling(Rig):
    """A body under gravity that nothing holds."""

    def declare(self):
        self.body = Mass(m=2.0)
        self.weight = Gravity(m=self.body.m)
        self.connect(self.weight.flange, self.body.flange_a)


class Between(Rig):
    """A body between two compression-only springs that both just touch it:
    its rest is unique, exactly at both kinks."""

    def declare(self):
        self.top, self.bottom = Fixed(), Fixed()
        self.a = Spring(k=1e6, compression_only=True)
        self.b = Spring(k=2e6, compression_only=True)
        self.body = Mass(m=1.0, s0=3e-3, v0=0.5)
        self.connect(self.top.flange, self.a.flange_a)
        self.connect(self.a.flange_b, self.body.flange_a)
        self.connect(self.body.flange_b, self.b.flange_a)
        self.connect(self.b.flange_b, self.bottom.flange)


def test_only_starts_without_solution_or_with_many_are_refused():
    with pytest.raises(ModelError, match=r"has no solution: der\(body\.v\) = 0 .*body\.s") as e:
        Falling().simulate(0.001, initial="steady")
    assert "\n" not in str(e.value)
    # the paper rig has no gravity: at rest, the hammer may lie anywhere above the piston
    with pytest.raises(ModelError, match=r"not determined.* leave hammer\.s, piston\.s free") as e:
        paper_rig().linearize("steady")
    assert "\n" not in str(e.value) and len(str(e.value)) < 160
    init = Between().simulate(0.001, n_out=3, initial="steady").initial
    assert abs(init["body.s"]) < 1e-15 and abs(init["body.v"]) < 1e-15


def test_initial_states_that_cannot_fix_themselves_say_which_would():
    # der(breech.s) = breech.v = 0 holds whatever breech.s
    with pytest.raises(ModelError) as e:
        paper_rig().simulate(0.001, initial=["breech.s"])
    msg = str(e.value)
    assert "der(breech.s) = 0 leaves breech.s free" in msg and msg.endswith(
        "; start breech.v at rest too") and "\n" not in msg and len(msg) < 160
    # der(breech.v) = 0 does not depend on breech.v (nothing on the breech
    # depends on its velocity), but on the positions of the breech and the piston
    with pytest.raises(ModelError) as e:
        paper_rig().simulate(0.001, initial=["piston.v", "breech.v"])
    msg = str(e.value)
    assert "touching nothing" not in msg
    assert "der(breech.v) = 0 leaves breech.v free" in msg
    assert msg.endswith("; start breech.s at rest too") and len(msg) < 160
    # the advice works: the breech on its mount under the weights above it
    rig = drop_rig()
    P = {p.name: p.value for p in rig.compile().params}
    init = rig.simulate(0.001, n_out=3, initial=["piston.v", "breech.v", "breech.s"]).initial
    assert init["breech.s"] == pytest.approx(statics({**P, "hammer.m": 0.0})[0], rel=1e-10)
    assert init.solved == ["piston.v", "breech.s", "breech.v"]


def test_cli_initial_refusal_names_the_states_to_add(tmp_path):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "paper",
                        "--initial", "piston.v,breech.v", "--json", "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1
    assert "start breech.s at rest too" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "drop-rest",
                        "--set", "contact.gap=0.001", "--t-end", "0.002", "--json",
                        "--out", str(tmp_path / "p")], capture_output=True, text=True,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    values = json.loads(r.stdout)["initial"]["values"]
    P = {p.name: p.value for p in drop_rig(rest=True).compile().params}
    assert values["hammer.s"] - values["piston.s"] - 1e-3 == \
        pytest.approx(statics(P)[2], rel=1e-8)
