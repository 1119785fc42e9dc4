"""The FMU's platforms: the win64 DLL (cross-compiled with MinGW-w64) of the
FMI 2.0 and the FMI 3.0 FMU depends on Windows' own DLLs only and, run under
Wine by a small FMI host compiled for win64 (tests/c/fmi_cs_host.c, FMI 2.0,
or 3.0 with -DFMI3), gives the Linux binary's peak;
bad platform requests are one-line errors that leave nothing behind."""
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest

import fmu_support as T  # noqa: E402
from pdbfs.errors import ExportError
from pdbfs.fmu import export_fmu
from pdbfs.fmu import platforms as P
from pdbfs.native.sundials import cache_root

MINGW = shutil.which("x86_64-w64-mingw32-gcc")
OBJDUMP = shutil.which("x86_64-w64-mingw32-objdump")
HOST_C = Path(__file__).with_name("c") / "fmi_cs_host.c"
#: where each FMI version keeps the win64 binary
WIN_DIR = {2: "win64", 3: "x86_64-windows"}
needs_mingw = pytest.mark.skipif(MINGW is None, reason="no MinGW-w64 (apt-get install gcc-mingw-w64-x86-64)")


def wine64():
    """Debian's wine64 loader: /usr/lib/wine/wine64 (package wine64), else on PATH."""
    for c in ("/usr/lib/wine/wine64", shutil.which("wine64"), shutil.which("wine")):
        if c and os.access(c, os.X_OK):
            return c
    return None


def _fmu(fmi_version):
    if MINGW is None:
        pytest.skip("no MinGW-w64 cross compiler (apt-get install gcc-mingw-w64-x86-64)")
    path = T.built_fmu("paper", fmi_version)
    with zipfile.ZipFile(path) as z:
        assert f"binaries/{WIN_DIR[fmi_version]}/pdbfs_paper.dll" in z.namelist(), "the default platforms include win64"
    return path


@pytest.fixture(scope="module")
def fmu_path():
    return _fmu(2)


@pytest.fixture(scope="module")
def fmu_path3():
    return _fmu(3)


def test_default_platforms_are_what_this_machine_builds():
    assert P.default_platforms()[0] == "linux64"
    assert ("win64" in P.default_platforms()) == (MINGW is not None)


@needs_mingw
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_win64_dll_depends_on_windows_dlls_only(fmi_version, tmp_path):
    if OBJDUMP is None:
        pytest.skip("no x86_64-w64-mingw32-objdump")
    dll = f"binaries/{WIN_DIR[fmi_version]}/pdbfs_paper.dll"
    with zipfile.ZipFile(_fmu(fmi_version)) as z:
        z.extract(dll, tmp_path)
    out = subprocess.run([OBJDUMP, "-p", str(tmp_path / dll)], capture_output=True, text=True, check=True).stdout
    dlls = re.findall(r"DLL Name:\s*(\S+)", out)
    assert dlls, out[:2000]
    system = re.compile(r"(?i)^(kernel32|msvcrt|ucrtbase|advapi32|user32|ntdll|api-ms-win-.*)\.dll$")
    assert all(system.match(d) for d in dlls), dlls
    exports = set(re.findall(r"\]\s+(fmi\d\w+)", out))
    wanted = {2: {"fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SetFMUstate"},
              3: {"fmi3InstantiateCoSimulation", "fmi3DoStep", "fmi3GetFloat64", "fmi3SetFMUState"}}
    assert wanted[fmi_version] <= exports and all(e.startswith(f"fmi{fmi_version}") for e in exports)


def _run_under_wine(fmu_path, tmp_path, dll=None, fmi_version=2):
    wine = wine64()
    if wine is None:
        pytest.skip("wine64 is not installed (apt-get install wine wine64)")
    tmp_path.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(tmp_path / "fmu")
        xml = z.read("modelDescription.xml").decode()
    guid = re.search(r'(?:guid|instantiationToken)="([^"]+)"', xml).group(1)
    vr = re.search(r'name="oil.pressure" valueReference="(\d+)"', xml).group(1)
    exe = tmp_path / "host.exe"
    subprocess.run([MINGW, "-O2", "-Wall", "-static", *(["-DFMI3"] if fmi_version == 3 else []),
                    f"-I{tmp_path / 'fmu' / 'sources'}", str(HOST_C), "-o", str(exe)],
                   check=True, capture_output=True, text=True)
    prefix = cache_root() / "wine64-prefix"   # made on Wine's first start (about 10 s), then reused
    prefix.parent.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "WINEPREFIX": str(prefix), "WINEDEBUG": "-all", "WINEDLLOVERRIDES": "mscoree,mshtml="}
    dll = dll or tmp_path / f"fmu/binaries/{WIN_DIR[fmi_version]}/pdbfs_paper.dll"
    r = subprocess.run([wine, str(exe), str(dll), guid, vr, "0.02", "1e-5"],
                       capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr[-3000:]
    m = re.search(r"peak (\S+) at (\S+)", r.stdout)
    assert m, r.stdout + r.stderr[-2000:]
    return float(m.group(1)), float(m.group(2))


@needs_mingw
def test_win64_dll_under_wine_gives_the_linux_peak(fmu_path, tmp_path):
    peak_win, t_win = _run_under_wine(fmu_path, tmp_path)
    r = fmpy.simulate_fmu(fmu_path, fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          output=["oil.pressure"])
    i = int(np.argmax(r["oil.pressure"]))
    peak_linux = float(r["oil.pressure"][i])
    assert peak_win == pytest.approx(peak_linux, rel=1e-9)
    assert t_win == pytest.approx(r["time"][i], abs=1e-12)
    # and it is the paper rig's pulse (the CasADi path on the same grid)
    _, rig = T.built_model("paper")
    _, p_ref = T.reference_pressure(rig)
    assert peak_win == pytest.approx(p_ref.max(), rel=1e-6)


@needs_mingw
def test_win64_dll_of_fmi3_under_wine_gives_the_fmi2_peak(fmu_path3, fmu_path, tmp_path):
    """The FMI 3.0 DLL, driven through the FMI 3.0 API under Wine, gives the
    FMI 2.0 DLL's peak (the same model code and co-simulation loop)."""
    peak3, t3 = _run_under_wine(fmu_path3, tmp_path / "v3", fmi_version=3)
    peak2, t2 = _run_under_wine(fmu_path, tmp_path / "v2")
    assert peak3 == pytest.approx(peak2, rel=1e-9) and t3 == pytest.approx(t2, abs=1e-12)
    r = fmpy.simulate_fmu(fmu_path3, fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          output=["oil.pressure"])
    assert peak3 == pytest.approx(float(np.max(r["oil.pressure"])), rel=1e-9)


@needs_mingw
def test_source_fmu_builds_for_windows_by_hand(fmu_path, tmp_path):
    """sources/README.txt's MinGW command line builds a DLL from sources/
    alone (SUNDIALS' C files included) that gives the shipped DLL's peak."""
    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(tmp_path / "fmu")
        readme = z.read("sources/README.txt").decode()
    assert "x86_64-w64-mingw32-gcc -O2 -shared -I. *.c sundials_src/*.c" in readme
    src = tmp_path / "fmu" / "sources"
    out = tmp_path / "own.dll"
    subprocess.run([MINGW, "-O2", "-shared", "-I.", *sorted(p.name for p in src.glob("*.c")),
                    *sorted(f"sundials_src/{p.name}" for p in (src / "sundials_src").glob("*.c")),
                    "-o", str(out), "-static"], cwd=src, check=True, capture_output=True, text=True)
    own, _ = _run_under_wine(fmu_path, tmp_path, dll=out)
    shipped, _ = _run_under_wine(fmu_path, tmp_path)
    assert own == pytest.approx(shipped, rel=1e-9)


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True, text=True)


def test_unknown_platform_is_one_line_exit_2(tmp_path):
    out = tmp_path / "x.fmu"
    r = _cli("export-fmu", "--platforms", "linux64,mac64", "-o", str(out))
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "mac64" in lines[0] and "linux64" in lines[0], r.stderr
    assert not out.exists() and not list(tmp_path.iterdir())


def test_missing_cross_compiler_names_the_debian_package(tmp_path, monkeypatch):
    monkeypatch.setitem(P.PLATFORMS, "win64", P.Platform(**{**P.PLATFORMS["win64"].__dict__,
                                                             "cc": "no-such-mingw-gcc"}))
    assert P.default_platforms() == ["linux64"]
    dae, _ = T.built_model("paper")
    with pytest.raises(ExportError, match="gcc-mingw-w64-x86-64") as err:
        export_fmu(dae, tmp_path / "x.fmu", platforms=["linux64", "win64"])
    assert "\n" not in str(err.value)
    assert not list(tmp_path.iterdir())
    # the CLI: the same line, exit status 2, no file (the cross compiler hidden through PATH)
    env_path = tmp_path / "bin"
    env_path.mkdir()
    for tool in ("gcc", "cc", "cmake"):
        if shutil.which(tool):
            os.symlink(shutil.which(tool), env_path / tool)
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--platforms", "win64", "-o",
                        str(tmp_path / "y.fmu")], capture_output=True, text=True,
                       env={**os.environ, "PATH": str(env_path)})
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "gcc-mingw-w64-x86-64" in r.stderr
    assert not (tmp_path / "y.fmu").exists()


def test_linux_only_export_has_no_win64_binary(tmp_path):
    _, rig = T.built_model("paper")
    path = rig.export_fmu(tmp_path / "l.fmu", platforms=["linux64"])
    with zipfile.ZipFile(path) as z:
        names = z.namelist()
    assert "binaries/linux64/pdbfs_paper.so" in names and not any(n.startswith("binaries/win64") for n in names)


def test_a_default_platform_whose_cvode_cannot_be_built_is_left_out(tmp_path, monkeypatch):
    """The Linux export never fails for want of a cross build; an explicit
    request for that platform does."""
    from pdbfs.fmu import export as E
    real = E.platform_sundials

    def no_win64(name):
        if name == "win64":
            raise ExportError("platform win64: no SUNDIALS for win64 (test)")
        return real(name)
    monkeypatch.setattr(E, "platform_sundials", no_win64)
    monkeypatch.setattr(E, "resolve_platforms", lambda p: ["linux64", "win64"] if p is None else
                        P.resolve_platforms(p))
    dae, _ = T.built_model("paper")
    with pytest.warns(RuntimeWarning, match="no win64 binary"):
        path = export_fmu(dae, tmp_path / "d.fmu")
    with zipfile.ZipFile(path) as z:
        assert not any(n.startswith("binaries/win64") for n in z.namelist())
        assert "win64" not in z.read("documentation/index.html").decode()
    if MINGW is not None:
        with pytest.raises(ExportError, match="win64"):
            export_fmu(dae, tmp_path / "e.fmu", platforms=["win64"])
        assert not (tmp_path / "e.fmu").exists()


@pytest.mark.parametrize("target", ["folder", "/proc/x.fmu"])
def test_unwritable_fmu_path_is_one_line_exit_2(tmp_path, target):
    out = str(tmp_path) if target == "folder" else target
    r = _cli("export-fmu", "-o", out)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and out in lines[0], r.stderr
    assert not list(tmp_path.iterdir())
