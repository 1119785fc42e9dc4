"""The wheel as a newcomer installs it: built from the repository, installed
without extras into a fresh virtual environment (pip as this machine has it
configured), the core commands run there, the example files are in the
package, the licence is in its metadata, and each feature of an extra says
in one line which extra to install. About two minutes (the install)."""
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.slow


def run(cmd, cwd, timeout=600, env=None):
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, cwd=cwd,
                          timeout=timeout, env=env)


@pytest.fixture(scope="module")
def core(tmp_path_factory):
    """(the wheel, a fresh environment with it installed without extras)."""
    base = tmp_path_factory.mktemp("wheel")
    r = run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", base / "dist", ROOT],
            base)
    assert r.returncode == 0, r.stderr[-2000:]
    wheel, = (base / "dist").glob("pdbfs-*.whl")
    r = run([sys.executable, "-m", "venv", base / "venv"], base)
    assert r.returncode == 0, r.stderr
    bindir = base / "venv" / ("Scripts" if os.name == "nt" else "bin")
    r = run([bindir / "python", "-m", "pip", "install", "-q", "--disable-pip-version-check",
             wheel], base, timeout=900)
    if r.returncode != 0 and ("No matching distribution" in r.stderr
                              or "Could not find a version" in r.stderr):
        pytest.skip(f"pip cannot reach the core's packages here: {r.stderr.strip()[-300:]}")
    assert r.returncode == 0, r.stderr[-2000:]
    return wheel, bindir


def test_the_wheel_carries_licence_and_example_data(core):
    wheel, _ = core
    with zipfile.ZipFile(wheel) as z:
        names = z.namelist()
        meta = z.read(next(n for n in names if n.endswith(".dist-info/METADATA"))).decode()
    assert "License-Expression: BSD-3-Clause" in meta and "License-File: LICENSE" in meta
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
    assert {"pdbfs/data/kistler_synthetic.csv", "pdbfs/data/gun_target.csv",
            "pdbfs/data/gun_firing.csv"} <= set(names)
    for extra in ("app", "dask", "parquet", "sensitivity", "all"):
        assert f"Provides-Extra: {extra}" in meta


def test_the_core_install_holds_no_extra(core):
    _, bindir = core
    r = run([bindir / "python", "-m", "pip", "list", "--format=freeze"], bindir)
    installed = {line.split("==")[0].lower() for line in r.stdout.split()}
    assert "pdbfs" in installed
    assert not installed & {"dash", "dask", "distributed", "pyarrow", "salib", "diskcache",
                            "multiprocess", "orjson"}, installed


def test_readmes_examples_run_from_the_core(core, tmp_path):
    """README's Python example and its commands, run as a newcomer would
    after `pip install pdbfs`: in the installed wheel's environment, from an
    empty folder, with nothing of the repository at hand."""
    import docs_examples as D
    _, bindir = core
    text = (ROOT / "README.md").read_text()
    code = "\n".join(b.body for b in D.python_blocks(text) if not b.skip)
    assert code.strip(), "README has no Python example"
    r = run([bindir / "python", "-c", code], tmp_path, timeout=900)
    assert r.returncode == 0, r.stderr[-2000:]
    shown = [c for c in D.commands(text) if not c.skip and not c.refused]
    assert shown, "README has no pdbfs command"
    for c in shown:
        args, _ = D.as_run(c.line)
        r = run([bindir / "pdbfs", *args], tmp_path, timeout=900)
        assert r.returncode == 0, f"{c.line}: {r.stderr[-1000:]}"


def test_simulate_export_fmu_and_modes_run_from_the_core(core, tmp_path):
    _, bindir = core
    pdbfs = bindir / "pdbfs"
    r = run([pdbfs, "simulate", "--json"], tmp_path)
    assert r.returncode == 0, r.stderr
    assert '"peak_pressure"' in r.stdout and list(tmp_path.iterdir()) == []
    r = run([pdbfs, "export-fmu", "-o", "rig.fmu"], tmp_path)
    assert r.returncode == 0, r.stderr
    with zipfile.ZipFile(tmp_path / "rig.fmu") as z:
        assert "modelDescription.xml" in z.namelist()
    r = run([pdbfs, "modes"], tmp_path)
    assert r.returncode == 0 and "omega" in r.stdout, r.stderr
    r = run([bindir / "python", "-c", "import pdbfs; p = pdbfs.example_data('kistler_synthetic"
             ".csv'); print(p.read_text().splitlines()[0])"], tmp_path)
    assert r.returncode == 0 and r.stdout.strip() == "time_s,pressure_Pa", r.stderr


@pytest.mark.parametrize("args,extra", [
    (["app"], "app"),
    (["sensitivity", "--range", "hammer.v0=2:4", "--n", "4"], "sensitivity"),
    (["sweep", "--set", "hammer.v0=2,3", "--format", "parquet", "--out", "s"], "parquet"),
    (["sweep", "--set", "hammer.v0=2,3", "--dask", "local"], "dask"),
], ids=lambda a: a if isinstance(a, str) else a[0])
def test_a_feature_of_an_extra_names_it(core, args, extra, tmp_path):
    _, bindir = core
    r = run([bindir / "pdbfs", *args], tmp_path)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"pip install 'pdbfs[{extra}]'" in lines[0], r.stderr
    assert list(tmp_path.iterdir()) == []
