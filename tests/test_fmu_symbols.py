"""A source-built FMU keeps everything but its FMI functions to itself
(fmu/symbols.py): two of them loaded with RTLD_GLOBAL into one process each
compute their own model, and two compiled with FMI2_FUNCTION_PREFIX link
into one program."""
import os
import shutil
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import fmpy
import numpy as np
import pytest

import fmu_support as T
from pdbfs.fmu.symbols import external_definitions

pytestmark = pytest.mark.skipif(shutil.which("cmake") is None or shutil.which("nm") is None
                                or sys.platform != "linux", reason="fmpy compile needs cmake; nm; ELF")

KINDS = ("paper", "hydraulic")
#: each rig's oil pressure
PRESSURE = {"paper": "oil.pressure", "hydraulic": "oil.p"}


def _peak(where, kind) -> float:
    r = fmpy.simulate_fmu(str(where), fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                          output=[PRESSURE[kind]])
    return float(np.max(r[PRESSURE[kind]]))


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    """kind -> (fmu, source-built unzipped folder)"""
    out = {}
    for kind in KINDS:
        fmu = T.built_fmu(kind)
        out[kind] = (fmu, T.source_build(fmu, tmp_path_factory.mktemp(kind)))
    return out


def _library(folder: Path) -> Path:
    return next((folder / "binaries" / "linux64").glob("*.so"))


def test_external_definitions_finds_definitions_not_declarations():
    c = textwrap.dedent("""
        #ifdef __cplusplus
        extern "C" {
        #endif
        static int hidden(int a) { return a; }
        int seen(int a);          /* a prototype: no definition */
        int seen(int a) { if (a) { return 1; } return 0; }
        double table[3] = {1, 2, 3};
        int counter;
        extern int elsewhere;
        typedef struct { int x; } S;
        struct T { int y; };
        const char *name(void) { return "int fake(void) {"; }
        #ifdef __cplusplus
        }
        #endif
    """)
    assert external_definitions(c) == {"seen", "table", "counter", "name"}


def test_only_fmi_functions_are_global(builds):
    for kind, (_, folder) in builds.items():
        syms = subprocess.run(["nm", "-g", "--defined-only", str(_library(folder))], capture_output=True,
                              text=True, check=True).stdout.split("\n")
        names = [line.split()[-1] for line in syms if len(line.split()) == 3]
        assert any(n == "fmi2DoStep" for n in names)
        prefix = os.path.commonprefix([n for n in names if not n.startswith("fmi2")])
        foreign = [n for n in names if not n.startswith("fmi2") and not n.startswith(prefix)]
        # every other symbol carries the model's own prefix (the model identifier and a hash)
        assert not foreign and len(prefix) > 10, (kind, foreign[:5], prefix)


def test_two_source_fmus_loaded_rtld_global_keep_their_models(builds):
    """FMPy opens each binary after both were loaded RTLD_GLOBAL: were the
    internal symbols shared, the second would run the first's model."""
    script = textwrap.dedent("""
        import ctypes, sys
        import fmpy, numpy as np
        libs = sys.argv[1::3]; folders = sys.argv[2::3]; outputs = sys.argv[3::3]
        for lib in libs:
            ctypes.CDLL(lib, mode=ctypes.RTLD_GLOBAL)
        for folder, out in zip(folders, outputs):
            r = fmpy.simulate_fmu(folder, fmi_type="CoSimulation", stop_time=0.02, output_interval=1e-5,
                                  output=[out])
            print(repr(float(np.max(r[out]))))
    """)
    args = []
    for kind in KINDS:
        folder = builds[kind][1]
        args += [str(_library(folder)), str(folder), PRESSURE[kind]]
    r = subprocess.run([sys.executable, "-c", script, *args], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    peaks = [float(v) for v in r.stdout.split()]
    for kind, got in zip(KINDS, peaks):
        assert got == pytest.approx(_peak(builds[kind][0], kind), rel=1e-7), kind
    # bound to paper's functions, paper-hydraulic's state (another size) gave 0.11 MPa
    assert len(peaks) == 2 and min(peaks) > 50e6


def test_two_fmus_with_function_prefixes_link_into_one_program(builds, tmp_path):
    cc = T.system_cc() or T.cmake_cc(tmp_path)          # zig cc where the system has none
    objs = []
    for kind, prefix in zip(KINDS, ("A_", "B_")):
        folder = builds[kind][1]
        md = fmpy.read_model_description(str(folder))
        files = md.buildConfigurations[0].sourceFileSets[0].sourceFiles
        for f in files:
            o = tmp_path / f"{prefix}{Path(f).name}.o"
            subprocess.run([cc, "-O1", "-c", f"-DFMI2_FUNCTION_PREFIX={prefix}", f"-I{folder / 'sources'}",
                            str(folder / "sources" / f), "-o", str(o)], check=True, capture_output=True)
            objs.append(o)
    host = Path(__file__).with_name("c") / "fmi2_two_models.c"
    exe = tmp_path / "two"
    r = subprocess.run([cc, "-O1", f"-I{builds['paper'][1] / 'sources'}", str(host), *map(str, objs),
                        "-o", str(exe), "-lm"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr[-3000:]
    args = []
    for kind in KINDS:
        md = fmpy.read_model_description(builds[kind][0])
        vr = next(v.valueReference for v in md.modelVariables if v.name == PRESSURE[kind])
        args += [md.guid, str(vr)]
    r = subprocess.run([str(exe), *args, "0.02", "1e-5"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    got = dict(line.split() for line in r.stdout.splitlines())
    for kind, key in zip(KINDS, "AB"):
        assert float(got[key]) == pytest.approx(_peak(builds[kind][0], kind), rel=1e-7), kind


def test_sources_include_the_names_header_first():
    with zipfile.ZipFile(T.built_fmu("paper", 3)) as z:
        cfiles = [n for n in z.namelist() if n.startswith("sources/") and n.endswith(".c")]
        firsts = {z.read(n).decode("latin-1").splitlines()[0] for n in cfiles}
        header = z.read("sources/pdbfs_names.h").decode()
    assert len(firsts) == 1 and '"pdbfs_names.h"' in firsts.pop()
    assert "FMI3_FUNCTION_PREFIX" in header and "#define CVodeCreate " in header
