"""The hydraulic rigs: paper-hydraulic reproduces the paper rig; the whole
tool (both back ends, the FMU, sweeps, design, calibration, the command
line) works on them unchanged; bad input is named."""
import json
import subprocess
import sys

import numpy as np
import pytest

import pdbfs
from pdbfs.components import Mass
from pdbfs.components.hydraulic import LaminarLeak, Orifice, Piston, Tank, Volume
from pdbfs.errors import ConnectError, ParameterError
from pdbfs.models import RIGS, hydraulic_pulse_rig, paper_hydraulic_rig, paper_rig
from pdbfs.rig import Rig


def test_paper_hydraulic_reproduces_the_paper_pulse():
    """K = k2*L/A, compliance referred to the start volume: the column is
    the paper's spring k2, slack included."""
    rig = paper_hydraulic_rig()
    assert rig.compile().params[[p.name for p in rig.parameters()].index("oil.K")].value == \
        pytest.approx(2.228e8 * 0.2 / 2.270e-2)
    a = rig.simulate(0.02, rtol=1e-10, atol=1e-12)
    b = paper_rig().simulate(0.02, rtol=1e-10, atol=1e-12)
    peak = np.max(b["oil.pressure"])
    assert np.max(np.abs(a["oil.p"] - b["oil.pressure"])) < 1e-6 * peak
    assert np.max(np.abs(a["piston.s"] - b["piston.s"])) < 1e-6 * np.max(b["piston.s"])
    sa, sb = a.summary(), b.summary()
    for k in sb:
        assert sa[k] == pytest.approx(sb[k], rel=1e-6), k


def test_seal_leak_lowers_the_pulse_and_loses_oil():
    base = paper_hydraulic_rig().simulate(0.02).summary()["peak_pressure"]
    res = paper_hydraulic_rig(leak="laminar").simulate(0.02, params={"leak.G": 1e-9})
    assert res.summary()["peak_pressure"] < base * (1 - 1e-3)
    assert np.max(res["leak.q"]) > 0 and np.min(res["leak.q"]) >= 0.0
    none = paper_hydraulic_rig(leak="orifice").simulate(0.02, params={"leak.A": 1e-12})
    assert none.summary()["peak_pressure"] == pytest.approx(base, rel=1e-5)


def test_a_stiffening_oil_raises_the_peak_and_shortens_the_pulse():
    const = paper_hydraulic_rig().simulate(0.02).summary()
    oil = RIGS["paper-hydraulic-oil"]().simulate(0.02).summary()
    assert oil["peak_pressure"] > const["peak_pressure"] * 1.05
    assert oil["pulse_duration"] < const["pulse_duration"]


@pytest.mark.parametrize("name", ["paper-hydraulic", "hydraulic-pulse"])
def test_casadi_and_compiled_back_ends_agree(name):
    rig = RIGS[name]()
    a = rig.simulate(0.02, rtol=1e-10, atol=1e-12)
    b = rig.simulate(0.02, rtol=1e-10, atol=1e-12, backend="c")
    sig = rig.compile().signals["pressure"]
    peak = np.max(a[sig])
    assert np.max(np.abs(a[sig] - b[sig])) < 1e-7 * peak
    assert a.summary()["peak_pressure"] == pytest.approx(b.summary()["peak_pressure"], rel=1e-7)


def test_compiled_bdf_on_a_one_state_rig():
    """A one-state rig has a full (1x1) Jacobian, which CasADi writes as a
    compressed dense pattern; the CVODE driver read it as sparse and crashed."""
    class One(Rig):
        def declare(self):
            self.vol = Volume(V=1e-3, K=1.5e9, p0=10e6)
            self.leak = LaminarLeak(G=1e-11)
            self.tank = Tank(p=0.0)
            self.connect(self.vol.port, self.leak.port_a)
            self.connect(self.leak.port_b, self.tank.port)
    rig = One()
    a = rig.simulate(0.02, method="bdf", backend="c", rtol=1e-10, atol=1e-12)
    want = 10e6 * np.exp(-1.5e9 * 1e-11 * a.t / 1e-3)
    assert np.max(np.abs(a["vol.p"] - want)) < 1e-7 * 10e6


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmu_of_the_pulse_rig_agrees_with_casadi(tmp_path, fmi_type):
    fmpy = pytest.importorskip("fmpy")
    rig = hydraulic_pulse_rig()
    path = rig.export_fmu(str(tmp_path / "pulse.fmu"))
    got = fmpy.simulate_fmu(str(path), stop_time=0.02, output_interval=1e-5, fmi_type=fmi_type,
                            output=["chamber.p"], relative_tolerance=1e-10)
    t, k = np.unique(got["time"], return_index=True)    # model exchange repeats event times
    ref = rig.simulate(0.02, t_out=t, rtol=1e-10, atol=1e-12)
    peak = np.max(ref["chamber.p"])
    assert np.max(np.abs(got["chamber.p"][k] - ref["chamber.p"])) < 1e-7 * peak
    md = fmpy.read_model_description(str(path))
    units = {v.name: (v.unit or (v.declaredType.unit if v.declaredType else None))
             for v in md.modelVariables}
    assert units["chamber.p"] == "Pa" and units["valve.A"] == "m2"


@pytest.mark.parametrize("backend", ["casadi", "c"])
def test_sweep_gives_the_single_runs(backend):
    rig = hydraulic_pulse_rig()
    sw = pdbfs.sweep(rig, {"valve.A": [6e-5, 8e-5]}, progress=False, backend=backend)
    assert len(sw) == 2 and not sw.failed
    for pt in sw:
        one = rig.simulate(0.02, params=pt.params).summary()
        for k, v in one.items():
            assert pt.summary[k] == pytest.approx(v, rel=1e-6), k
    peaks = sw.values("peak_pressure")
    assert peaks[1] > peaks[0]


def test_design_of_the_pulse_rig_reaches_its_targets():
    rig = hydraulic_pulse_rig()
    des = pdbfs.design(rig, {"peak_pressure": 80e6, "pulse_duration": 0.012},
                       free=["valve.A", "drain.A"])
    assert des.reachable
    got = rig.simulate(0.02, params=des.params).summary()
    assert got["peak_pressure"] == pytest.approx(80e6, rel=1e-4)
    assert got["pulse_duration"] == pytest.approx(0.012, rel=1e-4)


def test_sensitivity_of_the_pulse_rig_ranks_its_valves():
    sens = pdbfs.sensitivity(hydraulic_pulse_rig(), {"valve.A": (6e-5, 1e-4),
                                                     "drain.A": (3e-5, 5e-5)}, n=64)
    ix = sens.to_dict()["indices"]
    assert ix["peak_pressure"]["valve.A"]["ST"] > 3 * ix["peak_pressure"]["drain.A"]["ST"]
    assert ix["pulse_duration"]["drain.A"]["ST"] > 3 * ix["pulse_duration"]["valve.A"]["ST"]


def test_calibration_of_the_pulse_rig_recovers_the_valve():
    rig = hydraulic_pulse_rig()
    truth = {"valve.A": 7e-5}
    res = rig.simulate(0.02, n_out=401, params=truth)
    cal = pdbfs.calibrate(rig, (res.t, res["chamber.p"]), ["valve.A"], starts=1)
    assert cal.params["valve.A"] == pytest.approx(7e-5, rel=1e-5)


def test_command_line_simulates_and_lists_parameters(tmp_path):
    out = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "hydraulic-pulse",
                          "--json", "--out", str(tmp_path)], capture_output=True, text=True, check=True)
    summary = json.loads(out.stdout)
    assert summary["peak_pressure"] == pytest.approx(
        hydraulic_pulse_rig().simulate(0.02).summary()["peak_pressure"], rel=1e-6)
    out = subprocess.run([sys.executable, "-m", "pdbfs.cli", "params", "--rig", "paper-hydraulic"],
                         capture_output=True, text=True, check=True).stdout
    line = next(ln for ln in out.splitlines() if ln.startswith("oil.K "))
    assert " Pa " in line and "Bulk modulus" in line


def test_bad_values_are_named():
    for make, name in [(lambda: Volume(V=-1e-3), "Volume.V"), (lambda: Volume(K=0.0), "Volume.K"),
                       (lambda: Piston(A=-1.0), "Piston.A"), (lambda: Orifice(A=-1e-6), "Orifice.A"),
                       (lambda: Volume(p0=-1.0), "Volume.p0")]:
        with pytest.raises(ParameterError, match=name.replace(".", r"\.")):
            make()
    with pytest.raises(ParameterError, match="bulk-modulus law 'tait'"):
        Volume(law="tait")
    with pytest.raises(ParameterError, match="law 'air' needs absolute pressures"):
        paper_hydraulic_rig(law="air")
    with pytest.raises(ParameterError, match="seal leak 'gap'"):
        paper_hydraulic_rig(leak="gap")
    with pytest.raises(ParameterError, match="p_vap"):
        paper_hydraulic_rig().simulate(0.001, params={"oil.p_vap": -1.0})


def test_bad_value_on_the_command_line_is_one_line_and_exit_2():
    out = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "hydraulic-pulse",
                          "--set", "chamber.V=-1"], capture_output=True, text=True)
    assert out.returncode == 2
    err = out.stderr.strip()
    assert "chamber.V" in err and "\n" not in err and "Traceback" not in err


def test_flange_connected_to_a_port_is_refused_naming_both():
    class Wrong(Rig):
        def declare(self):
            self.mass = Mass()
            self.vol = Volume()
            self.connect(self.mass.flange_b, self.vol.port)
    with pytest.raises(ConnectError) as e:
        Wrong()
    msg = str(e.value)
    assert "mass.flange_b" in msg and "vol.port" in msg and "\n" not in msg


def test_open_port_is_closed_where_it_means_something_and_refused_elsewhere():
    class Sealed(Rig):                    # a chamber on its own: closed, keeps its pressure
        def declare(self):
            self.vol = Volume(p0=5e6)
    res = Sealed().simulate(0.01, n_out=3)
    assert np.allclose(res["vol.p"], 5e6)

    class Dangling(Rig):                  # an orifice open to nothing
        def declare(self):
            self.vol = Volume(p0=5e6)
            self.orifice = Orifice()
            self.connect(self.vol.port, self.orifice.port_a)
    with pytest.raises(ConnectError, match=r"orifice\.port_b .* not connected"):
        Dangling().compile()
