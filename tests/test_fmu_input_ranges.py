"""An FMU input declares the range and magnitude of what it drives: the
closed loop's plant's ``opening`` commands a CommandedValve, whose
``opening`` signal the valve clamps to 0..1 (its stops), so the input has
min 0, max 1 and nominal 1 (FMI 2.0 and 3.0), its description says who
clamps it, and a value set outside is said in the log (a warning: 5 acts
as 1); an input that drives no such signal declares only the
magnitude of its start. A start outside the range is refused at export."""
import xml.etree.ElementTree as ET
import zipfile

import fmpy
import fmpy.validation
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave

import fmu_support as T
import ssp_support as S
from pdbfs.components import blocks as B
from pdbfs.errors import ExportError, ModelError
from pdbfs.modelling import SignalInput

FMI_WARNING = 1


def _inputs(path):
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    out = {}
    for v in root.find("ModelVariables"):
        if v.get("causality") == "input":
            attrs = v[0].attrib if len(v) else v.attrib       # FMI 2.0: <Real .../>; 3.0: on <Float64>
            out[v.get("name")] = (v.get("description"), {k: attrs.get(k) for k in ("min", "max", "nominal")})
    return out


@pytest.mark.parametrize("version", [2, 3])
def test_the_inputs_declare_what_the_components_take(version):
    desc, attrs = _inputs(S.fmu_of("plant", version))["opening"]
    assert attrs == {"min": "0.0", "max": "1.0", "nominal": "1.0"}
    assert desc.endswith("(valve.opening clamps it to [0, 1])")
    desc, attrs = _inputs(S.fmu_of("controller", version))["measured"]
    assert attrs == {"min": None, "max": None, "nominal": "101325.0"} and "clamps" not in desc
    assert fmpy.validation.validate_fmu(S.fmu_of("plant", version)) == []


def _run(opening, name):
    """The plant's pressure after 2 ms with the valve commanded ``opening``, and its log."""
    path = S.fmu_of("plant")
    md = fmpy.read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    rec = T.Recorder(name)
    rec.clear()
    s = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=name)
    s.instantiate(callbacks=rec.callbacks)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    s.setReal([vr["opening"]], [opening])
    s.doStep(0.0, 2e-3)
    p = s.getReal([vr["sensor.y"]])[0]
    s.terminate()
    s.freeInstance()
    return p, rec.messages


def test_an_input_set_beyond_its_range_is_said_in_the_log():
    """Before, 5 behaved as 1 without a word."""
    p5, log5 = _run(5.0, "five")
    p1, log1 = _run(1.0, "one")
    p_half, _ = _run(0.5, "half")
    # (at 1 the valve's stop indicator is at its root: other steps, the same solution to the tolerance)
    assert p5 == pytest.approx(p1, rel=1e-8) and abs(p_half - p1) > 0.01 * p1
    warnings = [m for st, cat, m in log5 if st == FMI_WARNING]
    assert warnings == ["fmi2SetReal: input opening = 5 at t=0 is above its max 1: valve.opening clamps it "
                        "there, so it acts as 1"], log5
    assert not [m for st, _, m in log1 if st == FMI_WARNING]


def test_a_start_outside_the_range_is_refused_at_export(tmp_path):
    from input_rigs import CommandedPulse
    from pdbfs.fmu import export_fmu
    rig = CommandedPulse(command=B.Input("1", start=2.0, description="Valve command"))
    with pytest.raises(ExportError, match=r"input command starts at 2, outside \[0, 1\] where valve.opening "
                                          "clamps it") as err:
        export_fmu(rig.compile(), tmp_path / "c.fmu")
    assert "\n" not in str(err.value) and not list(tmp_path.iterdir())


@pytest.mark.parametrize("kw, words", [({"min": 1.0, "max": 0.0}, "min = 1.0 must be below max = 0.0"),
                                       ({"nominal": 0.0}, "nominal = 0.0 must be > 0"),
                                       ({"max": np.nan}, "max = nan must be a finite number")])
def test_a_signal_inputs_range_is_checked(kw, words):
    with pytest.raises(ModelError, match=words):
        SignalInput("1", "a command", **kw)
