"""The C math library (issue 22): a source FMU says that its build must link
libm on Linux (FMI 3.0: <Library name="m"> in buildDescription.xml for the
Linux platforms; both versions: sources/README.txt with FMPy's way to link
it), and a binary built so loads into a C host that links no libm, where
`fmpy compile`'s default one does not."""
import pathlib
import shutil
import subprocess
import sys
import zipfile

import fmpy
import pytest
from lxml import etree

import fmu_support as T

LINUX = sys.platform == "linux" and shutil.which("readelf") is not None


def _needed(lib: pathlib.Path) -> str:
    return subprocess.run(["readelf", "-d", str(lib)], capture_output=True, text=True, check=True).stdout


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None or not LINUX:
        pytest.skip("needs a C compiler and readelf on Linux")
    exe = tmp_path_factory.mktemp("host") / "dlopen_host"
    # no -lm: the host process has no libm unless the FMU brings it
    subprocess.run([cc, str(pathlib.Path(__file__).with_name("c") / "dlopen_host.c"), "-o", str(exe), "-ldl"],
                   check=True)
    assert "libm" not in _needed(exe)
    return exe


def test_build_description_names_libm_for_linux_only():
    schema = pathlib.Path(fmpy.__file__).parent / "schema" / "fmi3" / "fmi3BuildDescription.xsd"
    with zipfile.ZipFile(T.built_fmu("paper", 3)) as z:
        doc = etree.fromstring(z.read("sources/buildDescription.xml"))
        readme = z.read("sources/README.txt").decode()
    etree.XMLSchema(etree.parse(str(schema))).assertValid(doc)
    configs = {c.get("platform"): c for c in doc.iter("BuildConfiguration")}
    assert set(configs) == {"x86_64-linux", "aarch64-linux", None}
    libs = {p: [lib.get("name") for lib in c.iter("Library")] for p, c in configs.items()}
    assert libs["x86_64-linux"] == libs["aarch64-linux"] == ["m"] and libs[None] == []
    files = {p: [f.get("name") for f in c.iter("SourceFile")] for p, c in configs.items()}
    assert files["x86_64-linux"] == files[None]
    assert "-lm" in readme and "CMAKE_C_STANDARD_LIBRARIES" in readme


@pytest.mark.skipif(shutil.which("cmake") is None, reason="FMPy's build needs cmake")
@pytest.mark.parametrize("fmi_version", [2, 3])
def test_source_build_with_libm_loads_into_a_host_without_it(fmi_version, host, tmp_path):
    fmu = T.built_fmu("paper", fmi_version)
    with zipfile.ZipFile(fmu) as z:
        assert "-lm" in z.read("sources/README.txt").decode()
    plat = "linux64" if fmi_version == 2 else "x86_64-linux"
    fn = f"fmi{fmi_version}GetVersion"
    plain = T.source_build(fmu, tmp_path / "plain")
    lib = next((plain / "binaries" / plat).glob("*.so"))
    r = subprocess.run([str(host), str(lib), fn], capture_output=True, text=True)
    if "libm" not in _needed(lib):     # fmpy compile's default link: the defect README.txt warns of
        assert r.returncode == 1 and "undefined symbol" in r.stderr, r
    # README.txt's way: libm at the end of FMPy's link line
    linked = T.source_build(fmu, tmp_path / "linked", libraries="-lm")
    lib = next((linked / "binaries" / plat).glob("*.so"))
    assert "libm.so" in _needed(lib)
    r = subprocess.run([str(host), str(lib), fn], capture_output=True, text=True)
    assert r.returncode == 0 and r.stdout.strip() == f"{fmi_version}.0", r
