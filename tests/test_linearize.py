"""Linearization and modes against closed forms (to 1e-8): a mass on an oil
column, a two-mass chain, a damped oscillator, rigs with algebraic
variables (eliminated), and the paper rig with its contact linearised at
the hammer's static preload (matrices derived by hand below)."""
import json
import subprocess
import sys

import numpy as np
import pytest

from pdbfs.components import Damper, Fixed, Force, Mass, Spring
from pdbfs.components.hydraulic import LaminarLeak, Piston, Tank, Volume
from pdbfs.errors import ParameterError
from pdbfs.models import drop_rig, paper_rig
from pdbfs.rig import Rig
from hardening import Hardening


def close(a, b, rel=1e-8):
    return abs(a - b) <= rel * max(abs(a), abs(b))


class OilColumn(Rig):
    """A mass on a piston over a sealed chamber of oil."""
    m, A, V, K = 10.0, 1e-3, 1e-3, 1.5e9

    def declare(self):
        self.mass = Mass(m=self.m)
        self.piston = Piston(A=self.A)
        self.vol = Volume(V=self.V, K=self.K, p0=10e6, cavitation=False)
        self.connect(self.mass.flange_b, self.piston.flange)
        self.connect(self.piston.port, self.vol.port)


@pytest.mark.parametrize("at", ["start", 0.003])
def test_mass_on_an_oil_column(at):
    rig = OilColumn()
    modes = rig.linearize(at, params={"mass.v0": 0.5}).modes()
    want = np.sqrt(rig.K * rig.A ** 2 / (rig.V * rig.m))
    osc = [m for m in modes if m.omega > 1.0]
    assert len(osc) == 1 and close(osc[0].omega, want)
    assert abs(osc[0].damping) < 1e-12
    assert close(osc[0].frequency, want / (2 * np.pi))
    # the frame: the modes table has the same numbers
    df = rig.modes(at)
    assert close(float(df["omega"].iloc[-1]), want)


class TwoMass(Rig):
    """frame - k1 - m1 - k2 - m2 <- F (a force on the free end)."""

    def declare(self):
        self.frame = Fixed()
        self.k1 = Spring(k=4e6)
        self.m1 = Mass(m=3.0)
        self.k2 = Spring(k=1e6)
        self.m2 = Mass(m=2.0)
        self.load = Force(F=0.0)
        self.connect(self.frame.flange, self.k1.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.k2.flange_a)
        self.connect(self.k2.flange_b, self.m2.flange_a)
        self.connect(self.load.flange, self.m2.flange_b)


def test_two_mass_chain_eigenvalues_shapes_and_input_matrix():
    k1, k2, m1, m2 = 4e6, 1e6, 3.0, 2.0
    lin = TwoMass().linearize("start", inputs=["load.F"], outputs=["k1.f", "m2.s"])
    # det(K - w^2 M) = 0: m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0
    a, b, c = m1 * m2, -(m1 * k2 + m2 * (k1 + k2)), k1 * k2
    w2 = sorted([(-b - np.sqrt(b * b - 4 * a * c)) / (2 * a),
                 (-b + np.sqrt(b * b - 4 * a * c)) / (2 * a)])
    modes = lin.modes()
    assert len(modes) == 2
    for m, w in zip(modes, np.sqrt(w2)):
        assert close(m.omega, w) and abs(m.damping) < 1e-12
        # (k1 + k2 - m1 w^2) x1 = k2 x2, in the positions and in the velocities
        ratio = (k1 + k2 - m1 * w * w) / k2
        s = m.shape
        big, small = ("m1", "m2") if abs(ratio) < 1 else ("m2", "m1")
        for q in ("s", "v"):
            assert s[f"{big}.{q}"] == 1.0
            got = s[f"m2.{q}"] / s[f"m1.{q}"]
            assert close(got, ratio)
    # B: the force accelerates m2 only, 1/m2; C: the spring's force k1 s1; D = 0
    assert lin.states == ["m1.s", "m1.v", "m2.s", "m2.v"]
    assert np.allclose(lin.B.ravel(), [0, 0, 0, 1 / m2], rtol=1e-12, atol=0)
    assert np.allclose(np.abs(lin.C[0]), [k1, 0, 0, 0], rtol=1e-12, atol=0)
    assert np.allclose(lin.C[1], [0, 0, 1, 0]) and not lin.D.any()


class Damped(Rig):
    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=1e4)
        self.damper = Damper(c=30.0)
        self.mass = Mass(m=2.0, v0=1.0)
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.mass.flange_a)


def test_damped_oscillator_damping_ratio():
    (m,) = Damped().linearize().modes()
    assert close(m.omega, np.sqrt(1e4 / 2.0))
    assert close(m.damping, 30.0 / (2 * np.sqrt(1e4 * 2.0)))
    assert close(m.eigenvalue.imag, np.sqrt(1e4 / 2.0) * np.sqrt(1 - m.damping ** 2))


class Series(Rig):
    def declare(self):
        self.frame = Fixed()
        self.a = Hardening(k=3000.0, b=50.0)
        self.b = Hardening(k=6000.0, b=50.0)
        self.body = Mass(m=2.0, v0=1.0)
        self.connect(self.frame.flange, self.a.flange_a)
        self.connect(self.a.flange_b, self.b.flange_a)
        self.connect(self.b.flange_b, self.body.flange_a)


def test_algebraic_variables_are_eliminated():
    rig = Series()
    assert not rig.compile().is_ode
    (m,) = rig.linearize("start").modes()
    k = 1.0 / (1 / 3000.0 + 1 / 6000.0)      # springs in series
    assert close(m.omega, np.sqrt(k / 2.0))


class Joined(Rig):
    """Two cavitating volumes joined directly (one algebraic after index
    reduction) leaking through a laminar resistance to a tank."""

    def declare(self):
        self.a = Volume(V=1e-3, K=1.5e9, p0=10e6)
        self.b = Volume(V=2e-3, K=1.5e9, p0=10e6)
        self.leak = LaminarLeak(G=1e-11)
        self.tank = Tank(p=0.0)
        self.connect(self.a.port, self.b.port, self.leak.port_a)
        self.connect(self.leak.port_b, self.tank.port)


def test_hydraulic_dae_time_constant():
    lin = Joined().linearize("start", outputs=["b.p"])
    assert lin.A.shape == (1, 1)
    assert close(lin.A[0, 0], -1.5e9 * 1e-11 / 3e-3)       # K G / (Va + Vb)
    assert close(lin.C[0, 0], 1.0)                          # b.p follows a.p_law
    (m,) = lin.modes()
    assert m.damping == pytest.approx(1.0)


def by_hand(P, g):
    """A of the paper rig at rest under gravity, the contact linearised at the
    hammer's weight: k_c = n k d^(n-1), c_c = D d^n (the Hunt-Crossley term
    D d^n der(d)); oil k2 and mount k3 linear; seal c2 (+ F_c / v_eps)."""
    mh, mp, mb = P["hammer.m"], P["piston.m"], P["breech.m"]
    d = (mh * g / P["contact.k"]) ** (1 / P["contact.n"])
    kc = P["contact.n"] * P["contact.k"] * d ** (P["contact.n"] - 1)
    cc = P["contact.D"] * d ** P["contact.n"]
    k2, k3 = P["oil.k"], P["mount.k"]
    cs = P["seal.c"] + P["seal.F_c"] / P["seal.v_eps"]
    M = np.diag([mh, mp, mb])
    K = np.array([[kc, -kc, 0], [-kc, kc + k2, -k2], [0, -k2, k2 + k3]])
    C = np.array([[cc, -cc, 0], [-cc, cc + cs, 0], [0, 0, 0]])
    A = np.zeros((6, 6))
    pos, vel = [0, 2, 4], [1, 3, 5]                  # (s, v) of hammer, piston, breech
    A[np.ix_(pos, vel)] = np.eye(3)
    A[np.ix_(vel, pos)] = -np.linalg.solve(M, K)
    A[np.ix_(vel, vel)] = -np.linalg.solve(M, C)
    return A


def test_paper_rig_with_the_contact_linearised_at_a_static_preload():
    rig = drop_rig(rest=True)
    dae = rig.compile()
    P = {p.name: p.value for p in dae.params}
    assert P["oil.n"] == 1.0 and P["mount.n"] == 1.0
    lin = rig.linearize("start")
    want = by_hand(P, P["g"])
    assert lin.states == ["hammer.s", "hammer.v", "piston.s", "piston.v", "breech.s", "breech.v"]
    assert np.max(np.abs(lin.A - want)) <= 1e-8 * np.max(np.abs(want))
    lam = np.linalg.eigvals(want)
    lam = lam[lam.imag > 0]
    modes = lin.modes()
    assert len(modes) == 3
    for m, l in zip(modes, sorted(lam, key=abs)):
        assert close(m.omega, abs(l)) and close(m.damping, -l.real / abs(l))
    # at="steady" (every der(x) = 0) solves the same point as the rig's own equations
    steady = drop_rig(rest=True).linearize("steady")
    assert np.max(np.abs(steady.A - lin.A)) <= 1e-8 * np.max(np.abs(want))


def test_control_state_space_where_installed():
    control = pytest.importorskip("control")
    lin = TwoMass().linearize("start", inputs=["load.F"], outputs=["m2.s"])
    sys_ = lin.to_control()
    assert isinstance(sys_, control.StateSpace)
    # static gain: a force F stretches k1 and k2 in series
    assert close(float(np.squeeze(sys_.dcgain())), 1 / 4e6 + 1 / 1e6)
    assert sys_.state_labels == ["m1_s", "m1_v", "m2_s", "m2_v"]


def test_bad_arguments_are_refused():
    rig = paper_rig()
    with pytest.raises(ParameterError, match="not a parameter"):
        rig.linearize(inputs=["hammer.mass"])
    with pytest.raises(ParameterError, match="not a variable"):
        rig.linearize(outputs=["oil.p"])
    with pytest.raises(ParameterError, match="at='later'"):
        rig.linearize("later")
    with pytest.raises(ParameterError, match=">= 0"):
        rig.linearize(-1.0)


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_cli_modes(tmp_path):
    r = cli("modes", "--rig", "drop-rest", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    rig = drop_rig(rest=True)
    want = sorted(abs(l) for l in np.linalg.eigvals(by_hand(
        {p.name: p.value for p in rig.compile().params}, 9.80665)) if l.imag > 0)
    assert [m["omega"] for m in data["modes"]] == pytest.approx(want, rel=1e-8)
    r = cli("modes", "--rig", "paper", "--at", "0.004", cwd=tmp_path)
    assert r.returncode == 0 and "omega rad/s" in r.stdout and "hammer.v" in r.stdout
    # the drop rig at rest: the hammer lies on the piston, as in drop-rest
    r = cli("modes", "--rig", "drop", "--at", "steady", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert [m["omega"] for m in json.loads(r.stdout)["modes"]] == pytest.approx(want, rel=1e-8)
    # the paper rig has no gravity: at rest the hammer may lie anywhere above the piston
    r = cli("modes", "--rig", "paper", "--at", "steady", cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "hammer.s" in r.stderr
    r = cli("modes", "--rig", "paper", "--at", "soon", cwd=tmp_path)
    assert r.returncode == 2 and "--at" in r.stderr


def test_a_free_body_is_a_zero_mode_of_its_position_only():
    # the drop rig before the blow: the falling hammer touches nothing
    modes = drop_rig().linearize(0.1).modes()
    zero = [m for m in modes if m.damping is None]
    assert len(zero) == 2 and all(m.omega < 1e-9 for m in zero)
    for m in zero:
        assert abs(m.shape["hammer.s"]) == 1.0
        assert all(v == 0.0 for n, v in m.shape.items() if n != "hammer.s")
    # the piston and the breech on the oil and the mount, the seal damping the piston
    P = {p.name: p.value for p in drop_rig().compile().params}
    M = np.diag([P["piston.m"], P["breech.m"]])
    K = np.array([[P["oil.k"], -P["oil.k"]], [-P["oil.k"], P["oil.k"] + P["mount.k"]]])
    C = np.diag([P["seal.c"] + P["seal.F_c"] / P["seal.v_eps"], 0.0])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    want = sorted(abs(l) for l in np.linalg.eigvals(A) if l.imag > 0)
    got = [m.omega for m in modes if m.damping is not None]
    assert len(got) == 2 and all(close(a, b) for a, b in zip(got, want))
