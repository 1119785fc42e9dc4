"""What an FMU says about itself (issue 22): the rig's own model name and
description, what each event indicator marks (from its component),
solver.method's items as its range (version, author, licence and copyright:
test_fmu_rights.py)."""
import zipfile

import fmpy
import pytest

import fmu_support as T
from pdbfs.fmu import export_fmu
from pdbfs.models import hydraulic_pulse_rig


@pytest.fixture(scope="module")
def pulse_fmu3(tmp_path_factory):
    rig = hydraulic_pulse_rig()
    return str(export_fmu(rig.compile(), tmp_path_factory.mktemp("pulse") / "pulse.fmu", fmi_version=3)), rig


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_the_paper_rig_has_its_own_name_and_description(fmi_version):
    md = fmpy.read_model_description(T.built_fmu("paper", fmi_version))
    dae, rig = T.built_model("paper")
    assert md.modelName == dae.name == "pdbfs_paper"
    assert md.description.startswith("Pile-driver breech fatigue testing system") and "'pdbfs_paper'" in md.description


def test_the_pulse_rig_is_not_a_drop_hammer_and_its_indicators_are_valves(pulse_fmu3):
    fmu, rig = pulse_fmu3
    md = fmpy.read_model_description(fmu)
    assert md.modelName == "pdbfs_hydraulic_pulse"
    assert "valve" in md.description and "hammer" not in md.description.replace("without a hammer", "")
    ev = {v.name: v.description for v in md.modelVariables if v.name.startswith("event.")}
    valve = [t for n, t in ev.items() if n.startswith("event.valve.")]
    assert len(valve) == 4 and all("valve" in t for t in valve), ev
    assert not any("contact" in t for t in ev.values()), ev
    with zipfile.ZipFile(fmu) as z:
        page = z.read("documentation/index.html").decode()
    assert "drop-hammer" not in page and "the valve starts opening" in page


def test_indicators_say_what_they_mark():
    md = fmpy.read_model_description(T.built_fmu("hydraulic", 3))
    ev = {v.name: v.description for v in md.modelVariables if v.name.startswith("event.")}
    assert "cavitation" in ev["event.oil.cavitation"] and "cavitation ends" in ev["event.oil.cavitation_end"]
    assert "contact onset or separation" in ev["event.contact.hertz.indentation"]


def test_solver_method_range_is_its_items():
    with zipfile.ZipFile(T.built_fmu("paper")) as z:
        page = z.read("documentation/index.html").decode()
    row = next(r for r in page.split("<tr>")[1:] if "solver.method" in r)
    assert "0 (auto), 1 (BDF), 2 (Adams), 3 (ERK)" in row and "&infin;" not in row
