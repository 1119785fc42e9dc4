"""Linearization in the rig's real inputs: B and D of the mass-spring-damper
pushed by its input are 1/m and 0, its transfer function 1/(m s^2 + c s + k);
the commanded pulse rig's command -> pressure transfer function is the
analytic first-order one at its steady state, and its step response is the
nonlinear rig's small-signal response. ``pdbfs linearize`` writes A, B, C, D
with their names as JSON, .npz and .mat; ``pdbfs simulate --input`` reads a
command from a CSV file."""
import json
import math

import casadi as ca
import numpy as np
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.components import blocks as B
from pdbfs.models import RIGS

from input_rigs import COMMAND, C, CommandedPulse, K, M, Pushed

control = pytest.importorskip("control")

#: the commanded pulse rig's values (input_rigs.py; the components' defaults)
KB, V, CD, A_VALVE, A_DRAIN, RHO, DP_T, P_SUPPLY, P_TANK = \
    1.5e9, 1e-3, 0.7, 8e-5, 4e-5, 870.0, 1e5, 175e6, 101325.0


def test_b_and_the_transfer_function_of_the_pushed_mass():
    lin = Pushed().linearize(inputs=["u", "spring.k"], outputs=["body.s", "push.force"])
    order = [lin.states.index("body.s"), lin.states.index("body.v")]
    A = lin.A[np.ix_(order, order)]
    assert np.allclose(A, [[0.0, 1.0], [-K / M, -C / M]], rtol=1e-12, atol=0)
    assert lin.inputs == ["u", "spring.k"]
    assert np.allclose(lin.B[order, 0], [0.0, 1.0 / M], rtol=1e-12, atol=0)
    assert np.allclose(lin.B[order, 1], [0.0, 0.0], atol=0)     # at rest at s = 0: no pull
    assert np.allclose(lin.D, [[0.0, 0.0], [1.0, 0.0]], atol=0)   # the force is the input
    G = control.ss2tf(lin.to_control()[0, 0])
    num, den = np.ravel(G.num[0][0]), np.ravel(G.den[0][0])
    num, den = num / den[0], den / den[0]
    assert np.allclose(np.trim_zeros(num, "f"), [1.0 / M], rtol=1e-12)
    assert np.allclose(den, [1.0, C / M, K / M], rtol=1e-12)
    s = 2j * math.pi * 3.0
    assert lin.to_control()(s)[0, 0] == pytest.approx(1.0 / (M * s * s + C * s + K), rel=1e-12)


def _root(dp):
    return dp / (dp * dp + DP_T * DP_T) ** 0.25


def _root_slope(dp):
    q = dp * dp + DP_T * DP_T
    return q ** -0.25 - 0.5 * dp * dp * q ** -1.25


def test_the_command_to_pressure_transfer_function_of_the_valve():
    """Held at a half-open command, the chamber settles where inflow meets the
    drain's outflow; about there der(p) = K/V (q_valve - q_drain):
    A = -K/V (dq_valve/dp + dq_drain/dp), B = K/V Cd A sqrt(2/rho) root(p_s - p)."""
    rig = CommandedPulse(B.Input("1", start=0.5))
    lin = rig.linearize("steady", inputs=["command"], outputs=["chamber.p", "command.y"])
    p = lin.point["chamber.p_law"]
    k = CD * math.sqrt(2.0 / RHO)
    assert 0.5 * A_VALVE * _root(P_SUPPLY - p) == pytest.approx(A_DRAIN * _root(p - P_TANK),
                                                                rel=1e-9)
    b = KB / V * k * A_VALVE * _root(P_SUPPLY - p)
    a = -KB / V * k * (0.5 * A_VALVE * _root_slope(P_SUPPLY - p) + A_DRAIN * _root_slope(p - P_TANK))
    assert lin.A[0, 0] == pytest.approx(a, rel=1e-9) and lin.B[0, 0] == pytest.approx(b, rel=1e-9)
    assert lin.D[:, 0].tolist() == [0.0, 1.0]
    G = control.ss2tf(lin.to_control()[0, 0])
    assert G.den[0][0][-1] / G.den[0][0][0] == pytest.approx(-a, rel=1e-9)
    # the small-signal step response: the nonlinear rig, from the same steady state, the
    # command stepped by d: within d/u of the linear response (second order in d)
    t = np.linspace(0.0, 0.02, 201)
    _, y = control.step_response(lin.to_control(), T=t, input=0, output=0)
    errors = []
    for d in (1e-3, 1e-4):
        res = rig.simulate(0.02, t_out=t, start={"chamber.p_law": p}, inputs={"command": 0.5 + d},
                           rtol=1e-12, atol=1e-3)
        dp = res["chamber.p"] - p
        errors.append(np.max(np.abs(dp - d * y)) / np.max(np.abs(d * y)))
    assert errors[0] < 2e-3 and errors[0] / errors[1] == pytest.approx(10.0, rel=0.05)


@pytest.fixture
def commanded(monkeypatch):
    monkeypatch.setitem(RIGS, "commanded", CommandedPulse)
    monkeypatch.setitem(RIGS, "pushed", Pushed)
    return "commanded"


def test_pdbfs_linearize_writes_the_matrices_with_their_names(commanded, tmp_path, capsys):
    lin = Pushed().linearize(inputs=["u"], outputs=["body.s"])
    assert main(["linearize", "--rig", "pushed", "--inputs", "u", "--outputs", "body.s"]) in (0, None)
    data = json.loads(capsys.readouterr().out)
    assert (data["states"], data["inputs"], data["outputs"]) == (lin.states, ["u"], ["body.s"])
    for m in "ABCD":
        assert np.array_equal(np.array(data[m]), getattr(lin, m))
    for ext in (".json", ".npz", ".mat"):
        path = tmp_path / f"lin{ext}"
        assert main(["linearize", "--rig", "pushed", "--inputs", "u", "--outputs", "body.s",
                     "--out", str(path)]) in (0, None)
        if ext == ".json":
            got = json.loads(path.read_text())
            B_, names = np.array(got["B"]), got["states"]
        elif ext == ".npz":
            got = np.load(path)
            B_, names = got["B"], list(got["states"])
        else:
            from scipy.io import loadmat
            got = loadmat(path)
            B_, names = got["B"], [str(np.ravel(c)[0]) for c in np.ravel(got["states"])]
        assert np.array_equal(B_, lin.B) and names == lin.states, ext
    assert main(["linearize", "--rig", "pushed", "--out", str(tmp_path / "lin.txt")]) == 2
    assert not (tmp_path / "lin.txt").exists()
    assert "write .json, .npz or .mat" in capsys.readouterr().err


def test_pdbfs_simulate_reads_a_command_from_a_csv_file(commanded, tmp_path, capsys):
    """The command in ms with a header, the same run as the Python call."""
    t, u = COMMAND
    rows = "\n".join(f"{float(a) * 1e3!r},{float(b)!r}" for a, b in zip(t, u))
    (tmp_path / "command.csv").write_text("time [ms],command\n" + rows + "\n")
    out = tmp_path / "run"
    assert main(["simulate", "--rig", commanded, "--t-end", "0.02", "--input",
                 f"command={tmp_path / 'command.csv'}", "--out", str(out), "--json"]) in (0, None)
    summary = json.loads(capsys.readouterr().out)
    ms = np.array([float(a) * 1e3 for a in t])       # the file's times, read back in s
    direct = CommandedPulse().simulate(0.02, inputs={"command": (ms * 1e-3, u)}).summary()
    assert summary["peak_pressure"] == pytest.approx(direct["peak_pressure"], rel=1e-12)
    assert summary["stats"]["segments"] == 4
    header = (out / "results.csv").read_text().splitlines()[0]
    assert "command.y [1]" in header
    assert main(["params", "--rig", commanded]) in (0, None)
    listing = capsys.readouterr().out
    assert "\ninput " in listing and "command " in listing.split("\ninput ")[1]


def test_a_valve_commanded_to_its_closed_stop_is_linearized_on_its_open_side():
    """At the start the command is 0, the valve at its closed stop: the
    derivative in the command there is the mean of the two sides' (half the
    valve's gain, as it was). B is the open side's, K/V Cd A sqrt(2/rho)
    root(p_s - p), the same as a hair off the stop, and the kink is named
    with the side taken."""
    lin = CommandedPulse().linearize("start", inputs=["command"], outputs=["chamber.p"])
    p = lin.point["chamber.p_law"]
    b = KB / V * CD * math.sqrt(2.0 / RHO) * A_VALVE * _root(P_SUPPLY - p)
    assert lin.B[0, 0] == pytest.approx(b, rel=1e-6)
    off = CommandedPulse(B.Input("1", start=1e-9)).linearize(
        "start", inputs=["command"], outputs=["chamber.p"])
    assert lin.B[0, 0] == pytest.approx(off.B[0, 0], rel=1e-6)
    (kink,) = [k for k in lin.kinks if k.input == "command"]
    assert kink.law == "valve.closed" and kink.side == "> 0"
    assert "B and D in command taken on the side where it acts" in str(lin)


class Bent(B.SISO):
    """y = u + max(u, 0): a kink at u = 0 where both sides act, differently."""

    def equations(self):
        return [self.y.value - (self.u.value + ca.fmax(self.u.value, 0.0))]

    def events(self):
        return [(self.u.value, "bend", "u = 0")]


class BentPush(Pushed):
    """Pushed, its input through Bent."""

    def declare(self):
        self.bent = Bent(unit="N")
        super().declare()

    def connect(self, *connectors):
        if connectors == (self.u.y, self.push.u):
            super().connect(self.u.y, self.bent.u)
            super().connect(self.bent.y, self.push.u)
            return
        super().connect(*connectors)


def test_a_kink_in_an_input_whose_sides_both_act_is_refused():
    with pytest.raises(pdbfs.ParameterError) as err:
        BentPush().linearize("start", inputs=["u"], outputs=["body.s"])
    assert str(err.value).startswith("linearize: bent.bend (u = 0) is at its kink in input u")
    assert "\n" not in str(err.value)
    lin = BentPush(B.Input("N", start=1.0)).linearize("start", inputs=["u"])
    assert lin.B[lin.states.index("body.v"), 0] == pytest.approx(2.0 / M, rel=1e-12)


def test_linearize_refuses_an_output_listed_twice(capsys):
    with pytest.raises(pdbfs.ParameterError, match="outputs: 'body.s' is listed twice"):
        Pushed().linearize(inputs=["u"], outputs=["body.s", "body.s"])
    capsys.readouterr()
    assert main(["linearize", "--rig", "drop", "--outputs", "hammer.s,hammer.s"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.strip().endswith("--outputs 'hammer.s,hammer.s': hammer.s is listed twice")


def test_rig_linearize_says_it_takes_the_rigs_inputs():
    doc = pdbfs.Rig.linearize.__doc__
    assert "Names of the rig's inputs (held at their start values) and of its" in doc
    assert "Parameter names: the columns" not in doc
