"""The C math library (issue 22). A source FMU's binary calls tanh, pow, exp
... of libm; built without -lm on Linux it has no DT_NEEDED entry for libm
and loads only into a process that has libm already (Python has; a C host
may not). What the common tools read, and so how each is told:

- `fmpy compile` (FMPy 0.3.32) reads the source files, the preprocessor
  definitions and the C standard, not <Library>, and does not pass on its
  own --cmake-options: its binary lacks libm (the defect, shown here);
  CMake takes LDFLAGS from the environment on the first configure, which
  FMPy makes for every build, so `LDFLAGS="-Wl,--no-as-needed -lm" fmpy
  compile` gives a binary with libm (sources/README.txt says so);
- fmi-bd2cmake links the <Library> elements of the first build
  configuration, x86_64-linux's, which names libm: nothing to add.

Each binary is built by CMake with the system's C compiler, else zig cc (a
machine with pip alone), and loaded and simulated by a C host built by zig
cc with no -lm (tests/c/fmi_cs_host.c), checked to have no libm of its own."""
import pathlib
import re
import shutil
import subprocess
import sys
import zipfile

import fmpy
import pytest
from lxml import etree

import fmu_support as T
from pdbfs.native import toolchain

HOST_C = pathlib.Path(__file__).with_name("c") / "fmi_cs_host.c"
LINUX = sys.platform == "linux" and shutil.which("readelf") is not None
needs_cmake = pytest.mark.skipif(not LINUX or shutil.which("cmake") is None,
                                 reason="a source build needs cmake, readelf and Linux")
#: the link flags sources/README.txt gives for `fmpy compile`
LDFLAGS = "-Wl,--no-as-needed -lm"


def _needed(lib) -> list[str]:
    out = subprocess.run(["readelf", "-d", str(lib)], capture_output=True, text=True, check=True).stdout
    return re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", out)


def _unpacked(fmu, dest: pathlib.Path) -> pathlib.Path:
    """The FMU in ``dest`` without its binaries (a source-only FMU)."""
    with zipfile.ZipFile(fmu) as z:
        z.extractall(dest)
    shutil.rmtree(dest / "binaries")
    return dest


def _host(src: pathlib.Path, fmi_version: int, exe: pathlib.Path) -> pathlib.Path:
    cmd = [*toolchain.compiler("x86_64-linux"), "-O2", *(["-DFMI3"] if fmi_version == 3 else []),
           f"-I{src / 'sources'}", str(HOST_C), "-o", str(exe), "-ldl"]     # no -lm
    subprocess.run(cmd, capture_output=True, text=True, check=True)
    assert not any(n.startswith("libm.") for n in _needed(exe)), _needed(exe)
    return exe


def _simulate(host, lib, src: pathlib.Path):
    """(exit status, peak or None, stderr) of the host on ``lib``."""
    xml = (src / "modelDescription.xml").read_text()
    token = re.search(r'(?:guid|instantiationToken)="([^"]+)"', xml).group(1)
    vr = re.search(r'name="oil.pressure" valueReference="(\d+)"', xml).group(1)
    r = subprocess.run([str(host), str(lib), token, vr, "0.02", "1e-5"], capture_output=True, text=True)
    m = re.search(r"peak (\S+) at", r.stdout)
    return r.returncode, float(m.group(1)) if m else None, r.stderr


def _fmpy_compile(fmu, dest: pathlib.Path, env=None) -> pathlib.Path:
    """`fmpy compile` on a source-only copy of ``fmu``; returns it unpacked."""
    src = _unpacked(fmu, dest / "src")
    work = dest / "model.fmu"
    with zipfile.ZipFile(work, "w") as z:
        for f in sorted(src.rglob("*")):
            if f.is_file():
                z.write(f, f.relative_to(src).as_posix())
    r = subprocess.run([sys.executable, "-m", "fmpy.cli", "compile", str(work)], capture_output=True, text=True,
                       env={**T.cmake_env(dest), **(env or {})})
    assert r.returncode == 0, r.stderr[-3000:]
    built = dest / "built"
    with zipfile.ZipFile(work) as z:
        z.extractall(built)
    return built


@pytest.fixture(scope="module")
def reference():
    """The oil pressure's peak of the shipped (zig cc) FMI 2.0 binary, through FMPy."""
    r = fmpy.simulate_fmu(T.built_fmu("paper", 2), fmi_type="CoSimulation", stop_time=0.02,
                          output_interval=1e-5, output=["oil.pressure"])
    return float(max(r["oil.pressure"]))


def test_build_description_names_libm_first_and_for_linux_only():
    schema = pathlib.Path(fmpy.__file__).parent / "schema" / "fmi3" / "fmi3BuildDescription.xsd"
    with zipfile.ZipFile(T.built_fmu("paper", 3)) as z:
        doc = etree.fromstring(z.read("sources/buildDescription.xml"))
        readme = z.read("sources/README.txt").decode()
    etree.XMLSchema(etree.parse(str(schema))).assertValid(doc)
    configs = [c.get("platform") for c in doc.iter("BuildConfiguration")]
    # first: tools that take one configuration (FMPy, fmi-bd2cmake) take x86_64-linux's
    assert configs == ["x86_64-linux", "aarch64-linux", None]
    libs = {c.get("platform"): [lib.get("name") for lib in c.iter("Library")] for c in doc.iter("BuildConfiguration")}
    assert libs["x86_64-linux"] == libs["aarch64-linux"] == ["m"] and libs[None] == []
    assert f'LDFLAGS="{LDFLAGS}" fmpy compile' in readme and "fmi-bd2cmake" in readme


@needs_cmake
def test_fmpy_compile_without_libm_does_not_load_into_a_host_without_it(tmp_path):
    """the defect: FMPy's build reads nothing that adds libm"""
    if T.system_cc() is None:
        pytest.skip("no system C compiler: CMake builds with zig cc, which links libm by itself "
                    "(the defect shown here is the system compiler's)")
    built = _fmpy_compile(T.built_fmu("paper", 2), tmp_path)
    lib = built / "binaries" / "linux64" / "pdbfs_paper.so"
    assert not any(n.startswith("libm.") for n in _needed(lib)), _needed(lib)
    code, peak, err = _simulate(_host(built, 2, tmp_path / "host"), lib, built)
    assert code == 1 and peak is None and "undefined symbol" in err, err


@needs_cmake
def test_fmpy_compile_with_readmes_ldflags_runs_in_a_host_without_libm(tmp_path, reference):
    with zipfile.ZipFile(T.built_fmu("paper", 2)) as z:
        assert f'LDFLAGS="{LDFLAGS}" fmpy compile' in z.read("sources/README.txt").decode()
    built = _fmpy_compile(T.built_fmu("paper", 2), tmp_path, env={"LDFLAGS": LDFLAGS})
    lib = built / "binaries" / "linux64" / "pdbfs_paper.so"
    assert "libm.so.6" in _needed(lib)
    code, peak, err = _simulate(_host(built, 2, tmp_path / "host"), lib, built)
    assert code == 0, err
    assert peak == pytest.approx(reference, rel=1e-9)


@needs_cmake
def test_fmi_bd2cmake_links_libm_from_the_build_description(tmp_path, reference):
    pytest.importorskip("fmi_bd2cmake", reason="fmi-bd2cmake is a test extra (pip install fmi-bd2cmake)")
    src = _unpacked(T.built_fmu("paper", 3), tmp_path / "fmu")
    for cmd in ([sys.executable, "-c", "import sys; from fmi_bd2cmake.cli import main; sys.exit(main())"],
                ["cmake", "-S", ".", "-B", "build", "-DCMAKE_BUILD_TYPE=Release"],
                ["cmake", "--build", "build", "-j2"]):
        r = subprocess.run(cmd, cwd=src, capture_output=True, text=True, env=T.cmake_env(tmp_path))
        assert r.returncode == 0, (cmd, r.stdout[-2000:], r.stderr[-2000:])
    lib = next((src / "build" / "binaries" / "x86_64-linux").glob("*.so"))
    assert "libm.so.6" in _needed(lib)
    code, peak, err = _simulate(_host(src, 3, tmp_path / "host"), lib, src)
    assert code == 0, err
    assert peak == pytest.approx(reference, rel=1e-9)
