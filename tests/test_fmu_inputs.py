"""A rig's inputs in its FMU (FMI 2.0 and 3.0): declared as inputs with start,
unit and description and in the model structure; driven from FMPy (an input
table, and `fmpy simulate --input-file`) in Co-Simulation and Model
Exchange, a mass-spring-damper pushed through SignalForce matches its closed
form; held inputs converge at first order in the communication step,
inputs given with their derivative (FMI 2.0) at second order."""
import csv
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import fmpy
import fmpy.validation
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave

import ssp_support as S
from input_rigs import BaseExcited, msd_ramp, msd_sine, msd_step

F, T_STEP, A, FREQ = 10.0, 0.1, 5.0, 3.0      # N, s, N, Hz
SCALE = F / 400.0                              # the step's static deflection (m)


def description(fmu):
    with zipfile.ZipFile(fmu) as z:
        return ET.fromstring(z.read("modelDescription.xml"))


@pytest.mark.parametrize("version", [2, 3])
def test_the_input_is_declared_with_start_unit_description_and_dependencies(version):
    root = description(S.fmu_of("pushed", version))
    if version == 2:
        sv = {v.get("name"): v for v in root.iter("ScalarVariable")}
        u = sv["u"]
        assert (u.get("causality"), u.get("variability"), u.get("initial")) == ("input", "continuous", None)
        assert u[0].tag == "Real" and u[0].get("start") == "0.0" and u[0].get("unit") == "N"
        assert u.get("description") == "Force"
        assert root.find("CoSimulation").get("canInterpolateInputs") == "true"
        index = {v.get("name"): str(i) for i, v in enumerate(root.iter("ScalarVariable"), 1)}
        deps = {e.get("index"): e.get("dependencies").split() for e in root.find("ModelStructure/Derivatives")}
        outs = {e.get("index"): e.get("dependencies").split() for e in root.find("ModelStructure/Outputs")}
        assert index["u"] in deps[index["der(body.v)"]] and index["u"] not in deps[index["der(body.s)"]]
        assert outs[index["push.force"]] == [index["u"]]
    else:
        u = next(v for v in root.find("ModelVariables") if v.get("name") == "u")
        assert u.tag == "Float64" and u.get("causality") == "input" and u.get("start") == "0.0"
        assert u.get("unit") == "N" and u.get("initial") is None
        vr = u.get("valueReference")
        outs = [e for e in root.find("ModelStructure") if e.tag == "Output"]
        assert any(vr in e.get("dependencies").split() for e in outs)
    assert not fmpy.validation.validate_fmu(S.fmu_of("pushed", version))
    with zipfile.ZipFile(S.fmu_of("pushed", version)) as z:
        page = z.read("documentation/index.html").decode()
    assert "<h2>Inputs</h2>" in page and "<td><code>u</code></td><td>N</td>" in page


STEP = np.array([(0.0, 0.0), (T_STEP, 0.0), (T_STEP, F), (1.0, F)], dtype=[("time", float), ("u", float)])


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("kind", ["CoSimulation", "ModelExchange"])
def test_a_step_through_the_input_gives_the_closed_form(version, kind):
    r = fmpy.simulate_fmu(S.fmu_of("pushed", version), stop_time=1.0, output_interval=1e-3, input=STEP,
                          output=["body.s", "u"], fmi_type=kind, relative_tolerance=1e-10)
    # the step lands on a communication point: nothing but the solvers' error is left
    assert np.max(np.abs(r["body.s"] - msd_step(r["time"], F, T_STEP))) < 1e-7 * SCALE
    # the input read back is what FMPy set (its interpolation of the table rounds: 1e-15)
    after = r["time"] > T_STEP + 1e-9
    assert np.allclose(r["u"][after], F, rtol=1e-14, atol=0) and np.all(r["u"][r["time"] < T_STEP - 1e-9] == 0)


def test_fmpy_simulate_input_file(tmp_path):
    """The command line of FMPy drives the input from a CSV file."""
    csv_in, out = tmp_path / "in.csv", tmp_path / "out.csv"
    with open(csv_in, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "u"])
        w.writerows(STEP.tolist())
    cmd = [sys.executable, "-m", "fmpy", "simulate", S.fmu_of("pushed"), "--input-file",
           str(csv_in), "--output-file", str(out), "--stop-time", "1", "--output-interval", "1e-3",
           "--interface-type", "CoSimulation", "--relative-tolerance", "1e-10", "--output-variables",
           "body.s"]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    d = np.genfromtxt(out, delimiter=",", names=True)
    assert len(d) == 1001
    assert np.max(np.abs(d["bodys"] - msd_step(d["time"], F, T_STEP))) < 1e-7 * SCALE


class Slave:
    """The pushed mass's Co-Simulation instance (FMI 2.0) in FMPy."""

    def __init__(self, name="pushed", tolerance=1e-10):
        path = S.fmu_of("pushed")
        md = fmpy.read_model_description(path)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.s = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path),
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.s.instantiate()
        self.s.setupExperiment(tolerance=tolerance, startTime=0.0, stopTime=1.0)
        self.s.enterInitializationMode()
        self.s.exitInitializationMode()

    def get(self, *names):
        return self.s.getReal([self.vr[n] for n in names])

    def close(self):
        self.s.terminate()
        self.s.freeInstance()


def sine_run(h, slopes):
    """The largest deviation from the sine's closed form, co-simulated at
    the communication step h with the force held, or given with its slope."""
    s, err, w = Slave(f"sine{h}{slopes}"), 0.0, 2 * np.pi * FREQ
    for i in range(int(round(1.0 / h))):
        t = i * h
        s.s.setReal([s.vr["u"]], [A * np.sin(w * t)])
        if slopes:
            s.s.setRealInputDerivatives([s.vr["u"]], [1], [A * w * np.cos(w * t)])
        s.s.doStep(t, h)
        err = max(err, abs(s.get("body.s")[0] - msd_sine((i + 1) * h, A, FREQ)))
    s.close()
    return err


@pytest.mark.parametrize("slopes, expected", [(False, 1.0), (True, 2.0)])
def test_a_sine_converges_at_the_order_the_input_handling_promises(slopes, expected):
    steps = [1e-2, 5e-3, 2.5e-3, 1.25e-3]
    errors = [sine_run(h, slopes) for h in steps]
    assert S.order(steps, errors) == pytest.approx(expected, abs=0.05), errors
    # within the communication step's error: a held force lags by h/2
    amp = A / 400.0 * 2.2                           # the response's amplitude bound (m)
    bound = amp * 2 * np.pi * FREQ * steps[-1] if not slopes else amp * (2 * np.pi * FREQ * steps[-1]) ** 2
    assert errors[-1] < bound, (errors[-1], bound)


def test_an_input_reads_back_its_value_and_its_line():
    s = Slave("line")
    u = s.vr["u"]
    s.s.setReal([u], [2.0])
    assert s.get("u") == [2.0]
    s.s.setRealInputDerivatives([u], [1], [30.0])
    s.s.doStep(0.0, 0.01)
    assert s.get("u")[0] == pytest.approx(2.3, rel=1e-14)
    s.s.doStep(0.01, 0.01)                       # the line goes on until the input is set again
    assert s.get("u")[0] == pytest.approx(2.6, rel=1e-14)
    s.s.setReal([u], [1.0])                      # set: held from here
    s.s.doStep(0.02, 0.01)
    assert s.get("u") == [1.0]
    from fmpy.fmi1 import FMICallException
    for vr, order in (([u], [2]), ([s.vr["body.m"]], [1])):   # a second derivative; not an input
        with pytest.raises(FMICallException, match="status 3"):
            s.s.setRealInputDerivatives(vr, order, [1.0])
    assert s.get("u") == [1.0]                   # refused: nothing changed
    s.close()


@pytest.mark.parametrize("calls", ["value, slope, value", "slope, value", "value, slope"])
def test_a_slope_given_at_a_communication_point_is_kept_by_a_value_set_there(calls):
    """A master may give an input's slope before its value, or set the value
    again after the slope: at one communication point the order does not
    matter, and the force ramps as the closed form says (before, a value set
    after the slope dropped it: the force was held, 4e-4 m off)."""
    rate, h = 2000.0, 0.01                       # N/s, s
    s = Slave(f"order{calls}")
    u, err = s.vr["u"], 0.0
    for i in range(20):
        t = i * h
        for call in calls.split(", "):
            if call == "value":
                s.s.setReal([u], [rate * t])
            else:
                s.s.setRealInputDerivatives([u], [1], [rate])
        s.s.doStep(t, h)
        assert s.get("u")[0] == pytest.approx(rate * (t + h), rel=1e-14)
        err = max(err, abs(s.get("body.s")[0] - msd_ramp(t + h, rate, 0.0)))
    s.close()
    assert err < 1e-9 * rate * 20 * h / 400.0, err


def test_an_input_set_unchanged_does_not_restart_the_solver():
    """Setting an input to the value it has changes nothing: the trajectory
    does not depend on the communication step."""
    def run(h):
        s = Slave(f"same{h}")
        s.s.setReal([s.vr["u"]], [F])
        out = []
        for i in range(int(round(0.5 / h))):
            s.s.setReal([s.vr["u"]], [F])
            s.s.doStep(i * h, h)
            if abs(((i + 1) * h) % 0.05) < 1e-9 or abs(((i + 1) * h) % 0.05 - 0.05) < 1e-9:
                out.append(s.get("body.s")[0])
        s.close()
        return np.array(out)
    a, b = run(1e-3), run(5e-2)
    assert len(a) == len(b) == 10 and np.max(np.abs(a - b)) < 1e-12 * SCALE


def test_the_serialized_state_keeps_the_inputs():
    s = Slave("state")
    u = s.vr["u"]
    s.s.setReal([u], [3.0])
    s.s.setRealInputDerivatives([u], [1], [7.0])
    s.s.doStep(0.0, 0.01)
    saved = s.s.serializeFMUstate(s.s.getFMUstate())
    s.s.doStep(0.01, 0.01)
    after = s.get("body.s", "u")
    s.s.setReal([u], [0.0])
    state = s.s.deSerializeFMUstate(saved)
    s.s.setFMUstate(state)
    assert s.get("u")[0] == pytest.approx(3.07, rel=1e-14)
    s.s.doStep(0.01, 0.01)                # (the solver restarts from a restored state: its tolerance)
    x, u_now = s.get("body.s", "u")
    assert u_now == after[1] and x == pytest.approx(after[0], rel=1e-8)
    s.close()


def test_a_rig_that_differentiates_an_input_is_refused_in_one_line(tmp_path):
    from pdbfs.errors import ExportError
    from pdbfs.fmu import export_fmu
    with pytest.raises(ExportError, match=r"input base is differentiated") as err:
        export_fmu(BaseExcited().compile(), tmp_path / "b.fmu")
    assert "\n" not in str(err.value) and not list(tmp_path.iterdir())
