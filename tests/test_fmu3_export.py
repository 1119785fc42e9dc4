"""The FMI 3.0 FMU as a file: fmpy's validation, the same variables, units,
causalities and tunability as the 2.0 FMU, its model structure and event
indicators, buildDescription.xml, the binary's symbols, bad versions."""
import pathlib
import subprocess
import sys
import zipfile

import casadi as ca
import pytest

import fmpy
from fmpy import read_model_description
from fmpy.validation import validate_fmu
from lxml import etree

import fmu_support as T
from pdbfs.errors import ExportError
from pdbfs.fmu import export_fmu
from pdbfs.fmu.export import wrapper_files
from pdbfs.fmu.symbols import INCLUDE_LINE


@pytest.fixture(scope="module")
def path3():
    return T.built_fmu3("paper")


@pytest.fixture(scope="module")
def md2():
    return read_model_description(T.built_fmu("paper"))


@pytest.fixture(scope="module")
def md3(path3):
    return read_model_description(path3)


def test_validate_finds_nothing(path3):
    assert validate_fmu(path3) == []


def test_interfaces_and_token(md3, md2):
    assert md3.fmiVersion == "3.0"
    assert md3.coSimulation and md3.modelExchange and not md3.scheduledExecution
    assert md3.coSimulation.modelIdentifier == md2.coSimulation.modelIdentifier
    assert md3.guid.startswith("{") and md3.guid != md2.guid  # the instantiationToken
    for mi in (md3.coSimulation, md3.modelExchange):
        assert mi.canGetAndSetFMUstate and mi.canSerializeFMUstate
    assert md3.defaultExperiment.stopTime == md2.defaultExperiment.stopTime
    assert md3.defaultExperiment.tolerance == md2.defaultExperiment.tolerance


def test_same_variables_units_and_attributes_as_fmi2(md3, md2):
    v2 = {v.name: v for v in md2.modelVariables}
    v3 = {v.name: v for v in md3.modelVariables}
    dae = T.built_model("paper")[0]
    extra = {"time"} | {f"event.{n}" for n in dae.event_names}
    assert set(v3) == set(v2) | extra and not extra & set(v2)
    types = {"Real": "Float64", "Integer": "Int32", "Enumeration": "Enumeration"}
    for name, a in v2.items():
        b = v3[name]
        assert b.type == types[a.type], name
        for attr in ("valueReference", "causality", "variability", "initial", "unit", "min", "max",
                     "nominal", "declaredType"):
            x, y = getattr(a, attr), getattr(b, attr)
            if attr == "declaredType":
                x, y = x and x.name, y and y.name
            assert x == y, (name, attr, x, y)
        assert (a.start is None) == (b.start is None) and (a.start is None or float(a.start) == float(b.start))
        if a.derivative is not None:
            assert b.derivative.name == a.derivative.name, name
    def units(md):
        keys = ("kg", "m", "s", "A", "K", "mol", "cd", "rad", "factor", "offset")
        return {u.name: u.baseUnit and tuple(getattr(u.baseUnit, k) for k in keys) for u in md.unitDefinitions}
    u2, u3 = units(md2), units(md3)
    assert u2 == u3 and u3["Pa"][:3] == (1, -1, -2)
    assert v3["time"].causality == "independent" and v3["time"].unit == "s"
    assert v3["solver.method"].type == "Enumeration" and v3["solver.max_num_steps"].type == "Int32"


def test_model_structure_as_fmi2(md3, md2):
    def deps(unknowns):
        return {u.variable.name: sorted(d.name for d in u.dependencies) for u in unknowns}
    assert deps(md3.outputs) == deps(md2.outputs)
    assert deps(md3.derivatives) == deps(md2.derivatives)
    assert deps(md3.initialUnknowns) == deps(md2.initialUnknowns)


def test_event_indicators_are_the_rigs_events(md3):
    dae = T.built_model("paper")[0]
    names = [u.variable.name for u in md3.eventIndicators]
    assert names == [f"event.{n}" for n in dae.event_names] and md3.numberOfEventIndicators == len(names) == 3
    jac = ca.jacobian_sparsity(dae.events, dae.x)
    for k, u in enumerate(md3.eventIndicators):
        expected = sorted(dae.x_names[j] for j in range(len(dae.x_names)) if jac.has_nz(k, j))
        assert sorted(d.name for d in u.dependencies) == expected
    # contact onset: the gap closes between hammer and piston
    assert sorted(d.name for d in md3.eventIndicators[0].dependencies) == ["hammer.s", "piston.s"]


def test_build_description_lists_the_sources(path3):
    schema = pathlib.Path(fmpy.__file__).parent / "schema" / "fmi3" / "fmi3BuildDescription.xsd"
    with zipfile.ZipFile(path3) as z:
        names = set(z.namelist())
        text = z.read("sources/buildDescription.xml")
        shipped = {f.name: z.read(f"sources/{f.name}").decode() for f in wrapper_files(3)}
    doc = etree.fromstring(text)
    etree.XMLSchema(etree.parse(str(schema))).assertValid(doc)
    listed = [e.get("name") for e in doc.iter("SourceFile")]
    own = sorted(f.name for f in wrapper_files(3) if f.suffix == ".c") + ["pdbfs_model_funcs.c"]
    # CVODE's own C is listed too (a source FMU needs no SUNDIALS installed), so no external library
    assert set(own) <= set(listed) and {"sundials_src/cvodes.c", "sundials_src/nvector_serial.c"} <= set(listed)
    assert all(n in own or n.startswith("sundials_src/") for n in listed)
    assert {lib.get("name") for lib in doc.iter("Library")} == {"m"}   # the C math library only
    assert all(f"sources/{n}" in names for n in listed)
    assert "sources/sundials/LICENSE" in names and "documentation/licenses/SUNDIALS-LICENSE" in names
    assert {"sources/fmi3Functions.h", "sources/pdbfs_model.h", "binaries/x86_64-linux/pdbfs_paper.so"} <= names
    assert not any(n.startswith("sources/fmi2") for n in names)
    # one generic wrapper per version: the shipped files are the package's, and the loop is shared
    for f in wrapper_files(3):   # (C files: the private names' include on top, fmu/symbols.py)
        assert shipped[f.name] == (INCLUDE_LINE if f.suffix == ".c" else "") + f.read_text(), f.name
    assert {f.name for f in wrapper_files(2)} & {f.name for f in wrapper_files(3)} >= {
        "cosimulation.c", "model.c", "model_exchange.c", "pdbfs_cvode.c"}


def test_only_fmi3_symbols_are_exported(path3, tmp_path):
    with zipfile.ZipFile(path3) as z:
        so = z.extract("binaries/x86_64-linux/pdbfs_paper.so", tmp_path)
    nm = subprocess.run(["nm", "-D", "--defined-only", so], capture_output=True, text=True, check=True)
    exported = {line.split()[-1] for line in nm.stdout.splitlines() if line.split()[1] in "TDBR"}
    assert exported and all(s.startswith("fmi3") for s in exported), exported
    assert {"fmi3DoStep", "fmi3GetFloat64", "fmi3GetEventIndicators", "fmi3UpdateDiscreteStates",
            "fmi3SerializeFMUState", "fmi3InstantiateScheduledExecution"} <= exported


@pytest.mark.parametrize("version", [1, 4, "3", None, True, 2.5])
def test_bad_fmi_version_is_refused_before_any_work(tmp_path, version):
    dae = T.built_model("paper")[0]
    out = tmp_path / "x.fmu"
    with pytest.raises(ExportError, match="FMI version"):
        export_fmu(dae, out, fmi_version=version)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("version", ["4", "three"])
def test_cli_bad_fmi_version(tmp_path, version):
    out = tmp_path / "x.fmu"
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--fmi-version", version, "-o", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "FMI version" in lines[0] and repr(version) in lines[0], r.stderr
    assert list(tmp_path.iterdir()) == []


def test_cli_export_fmi3(tmp_path):
    out = tmp_path / "rig3.fmu"
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--fmi-version", "3", "-o", str(out)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    md = read_model_description(str(out))
    assert md.fmiVersion == "3.0" and validate_fmu(str(out)) == []
    # the same token as the Python API's export of the same rig
    assert md.guid == read_model_description(T.built_fmu3("paper")).guid


def test_shared_c_knows_no_fmi_version():
    """The co-simulation loop, Model Exchange, the model, variables and FMU
    state name no FMI type or call: the wrappers call into them, never the
    reverse (issue 15), so the 2.0 and 3.0 FMUs run the same code."""
    import re

    from pdbfs.fmu.export import C_DIR, COMMON_FILES, VERSION_FILES
    for name in COMMON_FILES:
        code = re.sub(r"/\*.*?\*/|//[^\n]*", "", (C_DIR / name).read_text(), flags=re.S)
        assert not re.search(r"fmi[23]\w*", code), (name, re.findall(r"fmi[23]\w*", code))
    for v, files in VERSION_FILES.items():
        for name in files:
            code = (C_DIR / name).read_text()
            include = "fmi2_prefix.h" if v == 2 and name != "fmi2_prefix.h" else f"fmi{v}Functions.h"
            assert f'#include "{include}"' in code and f"fmi{5 - v}" not in code, name


def test_version_neutral_c_calls_run_one_way():
    """No circle among the version-neutral C files (issue 22): the life cycle
    calls down into the interface parts and the model, never the reverse."""
    import re

    from pdbfs.fmu.export import C_DIR, COMMON_FILES
    from pdbfs.fmu.symbols import external_definitions
    files = [f for f in COMMON_FILES if f.endswith(".c")]
    texts = {f: re.sub(r"/\*.*?\*/", "", (C_DIR / f).read_text(), flags=re.S) for f in files}
    defined = {f: external_definitions(texts[f]) for f in files}
    calls = {f: {g for g in files if g != f and any(re.search(rf"\b{n}\s*\(", texts[f]) for n in defined[g])}
             for f in files}
    assert calls["model.c"] == set(), calls["model.c"]
    assert "lifecycle.c" not in set().union(*calls.values())
    assert "cosimulation.c" in calls["lifecycle.c"]

    def reach(f, seen=()):
        return set().union(*({g} | reach(g, seen + (f,)) for g in calls[f] if g not in seen)) if calls[f] else set()
    assert all(f not in reach(f) for f in files), calls
