"""The exported FMU as a file: binary, modelDescription.xml, sources, CLI."""
import dataclasses
import pathlib
import re
import subprocess
import sys
import zipfile

import casadi as ca
import numpy as np
import pytest

import fmpy
from fmpy import read_model_description  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

from pdbfs.fmu.symbols import INCLUDE_LINE
import fmu_support as T  # noqa: E402
from pdbfs.fmu import export_fmu  # noqa: E402
from pdbfs.fmu.export import WRAPPER_FILES  # noqa: E402
from pdbfs.fmu.variables import POSITIVE_MIN, RTOL_MAX, RTOL_MIN  # noqa: E402
from pdbfs.models import RIGS  # noqa: E402


@pytest.fixture(scope="module")
def fmu_path():
    return T.built_fmu("paper")


@pytest.fixture(scope="module")
def dae():
    return T.built_model("paper")[0]


@pytest.fixture(scope="module")
def md(fmu_path):
    return read_model_description(fmu_path)


def test_validate_finds_nothing(fmu_path):
    assert validate_fmu(fmu_path) == []


@pytest.mark.parametrize("interface", ["CoSimulation", "ModelExchange"])
def test_fmpy_cli_simulate_with_defaults(fmu_path, tmp_path, interface):
    out = tmp_path / "out.csv"
    r = subprocess.run([sys.executable, "-m", "fmpy.cli", "simulate", fmu_path, "--interface-type", interface,
                        "--output-file", str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    header = out.read_text().splitlines()[0]
    assert '"oil.pressure"' in header
    data = np.genfromtxt(out, delimiter=",", skip_header=1)
    assert data[-1, 0] == pytest.approx(0.02)
    col = header.split(",").index('"oil.pressure"')
    # the CasADi path's peak on the same grid (the one fmpy chose)
    t = np.unique(data[:, 0])
    p_ref = T.built_model("paper")[1].simulate(t_out=t, rtol=1e-8, atol=1e-10)["oil.pressure"]
    assert np.nanmax(data[:, col]) == pytest.approx(np.max(p_ref), rel=1e-6)


def test_binary_depends_only_on_libc_and_libm(fmu_path, tmp_path):
    with zipfile.ZipFile(fmu_path) as z:
        names = z.namelist()
        sos = [n for n in names if n.startswith("binaries/linux64/") and n.endswith(".so")]
        assert len(sos) == 1
        z.extract(sos[0], tmp_path)
    so = tmp_path / sos[0]
    r = subprocess.run(["ldd", str(so)], capture_output=True, text=True, check=True)
    libs = [line.split()[0] for line in r.stdout.strip().splitlines()]
    allowed = re.compile(r"^(linux-vdso\.so\.\d+|libc\.so\.6|libm\.so\.6|/lib64/ld-linux-x86-64\.so\.2|"
                         r"/lib/ld-linux.*)$")
    assert libs and all(allowed.match(lib) for lib in libs), r.stdout
    # only the FMI functions are exported (SUNDIALS and CasADi symbols stay hidden)
    nm = subprocess.run(["nm", "-D", "--defined-only", str(so)], capture_output=True, text=True, check=True)
    exported = [line.split()[-1] for line in nm.stdout.splitlines() if line.split()[1] in "TDBR"]
    assert exported and all(s.startswith("fmi2") for s in exported), exported


def test_sources_and_readme(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        names = set(z.namelist())
        readme = z.read("sources/README.txt").decode()
        shipped = {f.name: z.read(f"sources/{f.name}").decode() for f in WRAPPER_FILES}
    for f in ("pdbfs_model.h", "pdbfs_model_funcs.c", "pdbfs_model_funcs.h", "fmi2Functions.h",
              "README.txt"):
        assert f"sources/{f}" in names
    assert "SUNDIALS" in readme and "gcc" in readme
    # one generic wrapper for every rig: the shipped files are the package's
    assert {"fmi2_functions.c", "cosimulation.c", "pdbfs_cvode.c"} <= set(shipped)
    # ... with one line on top of each C file: the FMU's private names (fmu/symbols.py)
    for f in WRAPPER_FILES:
        expected = f.read_text()
        if f.suffix == ".c":
            expected = INCLUDE_LINE + expected
        assert shipped[f.name] == expected, f.name


def test_model_description(md, dae):
    assert md.fmiVersion == "2.0"
    assert md.coSimulation and md.modelExchange
    for mi in (md.coSimulation, md.modelExchange):
        assert mi.canBeInstantiatedOnlyOncePerProcess is False
        assert mi.canGetAndSetFMUstate is True
    assert md.numberOfEventIndicators == len(dae.event_names)
    de = md.defaultExperiment
    assert (float(de.startTime), float(de.stopTime)) == (0.0, 0.02)
    assert float(de.tolerance) <= 1e-7 and float(de.stepSize) > 0
    v = {sv.name: sv for sv in md.modelVariables}
    units = {u.name: u for u in md.unitDefinitions}
    for prm in dae.params:
        sv = v[prm.name]
        assert sv.causality == "parameter"
        assert sv.variability == ("tunable" if prm.tunable else "fixed")
        assert float(sv.start) == prm.value
        assert sv.unit == prm.unit and sv.description
        if prm.positive:   # FMI's min is inclusive: the smallest normal double stands for > 0
            assert float(sv.min) == max(prm.min or 0.0, POSITIVE_MIN) > 0
        elif prm.min is not None:
            assert float(sv.min) == prm.min
        if prm.max is not None:
            assert float(sv.max) == prm.max
    for name, (_, info) in dae.calculated.items():
        assert v[name].causality == "calculatedParameter"
    for info in dae.y_info:
        if info.output:
            assert v[info.name].causality == "output", info.name
    for name in ("solver.rtol", "solver.max_step", "solver.method"):
        assert v[name].causality == "parameter" and v[name].variability == "fixed"
    assert v["solver.method"].type == "Enumeration"
    assert (float(v["solver.rtol"].min), float(v["solver.rtol"].max)) == (RTOL_MIN, RTOL_MAX)
    # states and derivatives
    assert [s.variable.name for s in md.derivatives] == [f"der({n})" for n in dae.x_names]
    assert [v[f"der({n})"].derivative.name for n in dae.x_names] == dae.x_names
    # units: every unit used is defined; SI exponents where FMI can say them
    for sv in md.modelVariables:
        if sv.unit:
            assert sv.unit in units, sv.unit
    bu = units["Pa"].baseUnit
    assert (bu.kg, bu.m, bu.s) == (1, -1, -2)
    assert units["kg"].baseUnit.kg == 1
    assert (units["m/s"].baseUnit.m, units["m/s"].baseUnit.s) == (1, -1)


def test_model_structure(md, dae):
    deps = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.derivatives}
    assert deps["der(hammer.s)"] == ["hammer.v"]
    assert deps["der(hammer.v)"] == sorted(["hammer.s", "hammer.v", "piston.s", "piston.v"])
    assert "piston.v" not in deps["der(breech.v)"] and "breech.s" in deps["der(breech.v)"]
    outs = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.outputs}
    assert outs["oil.pressure"] == sorted(["piston.s", "breech.s"])
    assert outs["hammer.v"] == ["hammer.v"]
    init = {u.variable.name: sorted(d.name for d in u.dependencies) for u in md.initialUnknowns}
    assert init["hammer.v"] == ["hammer.v0"]
    assert "hammer.v0" in init["der(hammer.s)"]
    # and they are the CasADi sparsity
    jac = ca.jacobian(dae.ode, dae.x).sparsity()
    for i, n in enumerate(dae.x_names):
        expected = sorted(dae.x_names[j] for j in range(len(dae.x_names)) if jac.has_nz(i, j))
        assert deps[f"der({n})"] == expected


def test_guid_follows_the_model(tmp_path, md, dae):
    a = export_fmu(dae, tmp_path / "a.fmu")
    assert read_model_description(str(a)).guid == md.guid  # same model, same GUID
    params = list(dae.params)
    params[0] = dataclasses.replace(params[0], value=params[0].value + 1.0)
    changed = dataclasses.replace(dae, params=params)
    changed.__dict__.pop("_functions", None)
    b = export_fmu(changed, tmp_path / "b.fmu")
    assert read_model_description(str(b)).guid != md.guid
    assert re.fullmatch(r"\{[0-9a-f-]{36}\}", md.guid)


def test_algebraic_variables_are_refused(dae, tmp_path):
    z = ca.SX.sym("z")
    bad = dataclasses.replace(dae, z=z, alg=z - dae.x[0],
                              z_info=[dataclasses.replace(dae.x_info[0], name="aux")])
    bad.__dict__.pop("_functions", None)
    with pytest.raises(ValueError, match="algebraic"):
        export_fmu(bad, tmp_path / "bad.fmu")


def test_second_rig_with_more_masses():
    path = T.built_fmu("split3")
    dae, rig = T.built_model("split3")
    assert validate_fmu(path) == []
    md = read_model_description(path)
    assert md.numberOfContinuousStates == len(dae.x_names) > 6
    t_ref, p_ref = T.reference_pressure(rig)
    for fmi_type in ("CoSimulation", "ModelExchange"):
        r = fmpy.simulate_fmu(path, fmi_type=fmi_type, stop_time=0.02, output_interval=1e-5,
                              output=["oil.pressure"])
        t, idx = np.unique(r["time"], return_index=True)
        p = r["oil.pressure"][idx]
        peak = np.max(p_ref)
        assert np.max(p) == pytest.approx(peak, rel=1e-6)
        assert np.max(np.abs(np.interp(t_ref, t, p) - p_ref)) < 1e-6 * peak


def _simulated_peak(path):
    r = fmpy.simulate_fmu(str(path), fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          output=["oil.pressure"])
    assert r["time"][-1] == pytest.approx(0.02)
    return np.max(r["oil.pressure"])


CLI_RIGS = ["paper"] + [name for name in ("split-piston",) if name in RIGS]


@pytest.mark.parametrize("rig_name", CLI_RIGS)
def test_cli_export_fmu(tmp_path, rig_name):
    """`pdbfs export-fmu --rig NAME -o X.fmu` writes an FMU whose binary
    simulates the rig (fmpy's validation reads only the XML)."""
    out = tmp_path / f"{rig_name}.fmu"
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--rig", rig_name, "-o", str(out)],
                       capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert out.is_file() and str(out) in r.stdout
    assert validate_fmu(str(out)) == []
    rig = RIGS[rig_name]()
    dae = rig.compile()
    md = read_model_description(str(out))
    assert md.numberOfContinuousStates == len(dae.x_names)
    assert {v.name for v in md.modelVariables} >= set(dae.p_names) | set(dae.x_names)
    if rig_name == "paper":  # the same model as the one the tests export: same GUID
        assert md.guid == read_model_description(T.built_fmu("paper")).guid
    _, p_ref = T.reference_pressure(rig)
    assert _simulated_peak(out) == pytest.approx(np.max(p_ref), rel=1e-6)


def test_cli_export_fmu_unknown_rig(tmp_path):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--rig", "no-such-rig", "-o",
                        str(tmp_path / "x.fmu")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "no-such-rig" in r.stderr
    assert not (tmp_path / "x.fmu").exists()


def test_rig_export_fmu(tmp_path):
    """Rig.export_fmu(path) is export_fmu(rig.compile(), path)."""
    dae, rig = T.built_model("paper")
    path = rig.export_fmu(tmp_path / "rig.fmu")
    assert pathlib.Path(path) == tmp_path / "rig.fmu" and pathlib.Path(path).is_file()
    assert validate_fmu(str(path)) == []
    assert read_model_description(str(path)).guid == read_model_description(T.built_fmu("paper")).guid
    _, p_ref = T.reference_pressure(rig)
    assert _simulated_peak(path) == pytest.approx(np.max(p_ref), rel=1e-6)
