"""pdbfs.native.sundials: SUNDIALS' sources from the pinned PyPI sdist
(hash checked, only what CVODE needs extracted), CVODE compiled once per
target by zig cc into the cache under a lock; pdbfs holds no SUNDIALS code,
no CMake, apt or Unix-only call on the build path."""
import ast
import hashlib
import re
import subprocess
import threading
from pathlib import Path

import pytest

from pdbfs.native import sundials as S
from pdbfs.native import toolchain

ROOT = Path(__file__).resolve().parents[1]


def test_a_sdist_with_another_hash_is_refused(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    bad = tmp_path / S.SDIST
    bad.write_bytes(b"not amici")
    monkeypatch.setenv("PDBFS_SUNDIALS_SDIST", str(bad))
    with pytest.raises(S.SundialsNotFound, match="SHA-256") as err:
        S.find_sundials_sources()
    assert hashlib.sha256(b"not amici").hexdigest() in str(err.value)
    assert not (S.cache_root() / f"sundials-{S.VERSION}").exists()
    monkeypatch.setenv("PDBFS_SUNDIALS_SDIST", str(tmp_path / "missing.tar.gz"))
    with pytest.raises(S.SundialsNotFound, match="missing.tar.gz"):
        S.find_sundials_sources()


def test_only_what_cvode_needs_is_extracted_with_the_licence():
    src = S.find_sundials_sources()
    files = [p.relative_to(src.root).as_posix() for p in src.root.rglob("*") if p.is_file()]
    assert all(re.fullmatch(r"(src|include)/.+\.[ch]|LICENSE|ORIGIN", f) for f in files), files
    assert not any("idas" in f or "CMakeLists" in f for f in files)
    for c in S.SUNDIALS_C:
        assert (src.src / c).is_file(), c
    assert "BSD" in src.license.read_text() or "Redistribution" in src.license.read_text()
    config = (src.include / "sundials" / "sundials_config.h").read_text()
    assert '#define SUNDIALS_VERSION "7.1.1"' in config and "@" not in config
    assert S.SDIST_SHA256 in (src.root / "ORIGIN").read_text()


def test_cvode_is_compiled_once_per_target(monkeypatch):
    sd = S.find_sundials()
    lib = sd.libraries[0]
    mtime = lib.stat().st_mtime_ns
    calls = []
    monkeypatch.setattr(S, "_compile_all", lambda *a: calls.append(a))
    again = [None, None]

    def get(i):
        again[i] = S.find_sundials()
    threads = [threading.Thread(target=get, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert again[0] == again[1] == sd and not calls and lib.stat().st_mtime_ns == mtime
    assert sd.target == toolchain.host_target() and sd.version == "7.1.1"
    assert "-O2" in sd.origin


def test_the_archive_holds_cvode_and_exports_nothing_of_it_from_a_binary():
    sd = S.find_sundials()
    r = subprocess.run([*toolchain.archiver(), "t", str(sd.libraries[0])], capture_output=True, text=True,
                       check=True)
    members = set(r.stdout.split())
    assert {"cvodes.o", "nvector_serial.o", "sunlinsol_band.o", "sundials_context.o"} <= members
    assert len(members) == len(S.SUNDIALS_C)


def test_no_sundials_code_cmake_apt_or_unix_only_call_in_pdbfs():
    assert not list(ROOT.glob("pdbfs/native/*.sh"))
    for path in [*ROOT.glob("pdbfs/**/*.py"), *ROOT.glob("fmu/*.py")]:
        tree = ast.parse(path.read_text())
        imported = {a.name for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom))
                    for a in n.names} | {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        assert not imported & {"fcntl", "pwd", "grp", "termios"}, path
        text = path.read_text()
        assert "apt-get" not in text and "cmake -S" not in text, path
    for path in [*ROOT.rglob("*.c"), *ROOT.rglob("*.h")]:
        if ".venv" in path.parts:
            continue
        assert "Lawrence Livermore National Security" not in path.read_text(errors="replace"), path
