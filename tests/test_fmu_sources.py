"""The FMU carries what builds its binary (the model and wrapper C, CVODE's
sources, SUNDIALS' licence), declared as <SourceFiles> under both
interfaces (FMI 2.0) or in sources/buildDescription.xml (FMI 3.0): FMPy
compiles either with binaries/ removed and the result gives the shipped
binary's peak. documentation/index.html lists every parameter."""
import html
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile

import fmpy
import numpy as np
import pytest

import fmu_support as T  # noqa: E402


@pytest.fixture(scope="module")
def fmu_path():
    return T.built_fmu("paper")


def _peak(fmu, fmi_type="CoSimulation"):
    r = fmpy.simulate_fmu(str(fmu), fmi_type=fmi_type, stop_time=0.02, output_interval=1e-5,
                          output=["oil.pressure"])
    return float(np.max(r["oil.pressure"]))


def test_source_files_declared_under_both_interfaces(fmu_path):
    with zipfile.ZipFile(fmu_path) as z:
        names = set(z.namelist())
        root = ET.fromstring(z.read("modelDescription.xml"))
        licence = z.read("sources/sundials/LICENSE").decode()
        assert z.read("documentation/licenses/SUNDIALS-LICENSE").decode() == licence
        readme = z.read("sources/README.txt").decode()
    assert "BSD" in licence or "Redistribution and use" in licence
    lists = [[f.get("name") for f in root.findall(f"{k}/SourceFiles/File")] for k in ("ModelExchange",
                                                                                      "CoSimulation")]
    assert lists[0] == lists[1] and lists[0]
    assert all(f"sources/{f}" in names for f in lists[0])
    assert {"fmi2_functions.c", "cosimulation.c", "pdbfs_model_funcs.c", "sundials_src/cvodes.c",
            "sundials_src/nvector_serial.c"} <= set(lists[0])
    assert "sundials_src/*.c" in readme and "SourceFiles" in readme


def _works(*cmd):
    try:
        return subprocess.run(cmd, capture_output=True, timeout=60).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


@pytest.mark.skipif(not (_works("cmake", "--version") and _works("cc", "--version")),
                    reason="fmpy compile needs CMake and the system's C compiler")
@pytest.mark.parametrize("fmi_version, linux_dir", [(2, "linux64"), (3, "x86_64-linux")])
def test_fmpy_compile_builds_the_source_fmu(fmi_version, linux_dir, tmp_path):
    """`fmpy compile` on the FMU without binaries/ (FMPy's CLI, its CMake)."""
    fmu_path = T.built_fmu("paper", fmi_version)
    src = tmp_path / "source.fmu"
    with zipfile.ZipFile(fmu_path) as zin, zipfile.ZipFile(src, "w", zipfile.ZIP_DEFLATED) as zout:
        for info in zin.infolist():
            if not info.filename.startswith("binaries/"):
                zout.writestr(info, zin.read(info))
    r = subprocess.run([sys.executable, "-c", "import sys; from fmpy.cli import main; sys.exit(main())",
                        "compile", str(src)], capture_output=True, text=True)
    assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    with zipfile.ZipFile(src) as z:
        assert f"binaries/{linux_dir}/pdbfs_paper.so" in z.namelist()
    assert _peak(src) == pytest.approx(_peak(fmu_path), rel=1e-9)
    assert _peak(src, "ModelExchange") == pytest.approx(_peak(fmu_path, "ModelExchange"), rel=1e-9)


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_documentation_lists_every_parameter(fmi_version):
    dae, _ = T.built_model("paper")
    with zipfile.ZipFile(T.built_fmu("paper", fmi_version)) as z:
        page = z.read("documentation/index.html").decode()
    assert f"An FMI {fmi_version}.0 FMU" in page
    assert ("modelDescription.xml" if fmi_version == 2 else "buildDescription.xml") in page
    rows = {}
    for row in re.findall(r"<tr>(.*?)</tr>", page):
        cells = [html.unescape(re.sub(r"<[^>]+>", "", c)) for c in re.findall(r"<td>(.*?)</td>", row)]
        if cells:
            rows.setdefault(cells[0], cells)
    for p in dae.params:
        assert p.name in rows, p.name
        cells = rows[p.name]
        assert cells[1] == p.unit and cells[4] == ("tunable" if p.tunable else "fixed"), cells
        assert p.description in cells[5]
        if p.positive:
            assert "> 0" in cells[3]
    for name in ("solver.rtol", "solver.max_step", "solver.method", "solver.max_num_steps", "oil.pressure"):
        assert name in rows, name
    assert "SUNDIALS 7.1.1" in page and "x86_64-linux" in page and "pdbfs " in page
