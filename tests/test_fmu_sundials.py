"""pdbfs.native.sundials: search order, the CMake build (built once, cached)
and its fallback. Offline: the build is replaced by a stub, the caches by
fake prefixes; the last test checks the real build on this machine."""
import os
import subprocess
import time
import warnings

import pytest

from pdbfs.native import sundials as S


def fake_prefix(root, version="6.4.1"):
    (root / "include" / "cvode").mkdir(parents=True)
    (root / "include" / "sundials").mkdir()
    (root / "include" / "cvode" / "cvode.h").write_text("")
    (root / "include" / "sundials" / "sundials_config.h").write_text(f'#define SUNDIALS_VERSION "{version}"\n')
    (root / "lib").mkdir()
    (root / "lib" / "libsundials_cvode.a").write_bytes(b"!<arch>\n")
    return root


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("PDBFS_SUNDIALS_DIR", raising=False)
    monkeypatch.delenv("PDBFS_SUNDIALS_BUILD", raising=False)
    system = fake_prefix(tmp_path / "usr")   # the system's SUNDIALS
    monkeypatch.setattr(S, "_system", lambda: S.from_prefix(system, "system"))
    return tmp_path / "pdbfs"


def test_the_cmake_build_is_preferred_and_built_once(cache, monkeypatch):
    calls = []

    def build(dest, source=None, target="native"):
        calls.append(dest)
        return fake_prefix(dest)

    monkeypatch.setattr(S, "build", build)
    for _ in range(2):
        s = S.find_sundials()
        assert s.include_dir == cache / "sundials-cmake" / "include" and "CMake" in s.origin
    assert calls == [cache / "sundials-cmake"]
    # without fetching, an existing build is still used
    assert S.find_sundials(fetch=False).include_dir == cache / "sundials-cmake" / "include"


def test_a_failed_build_falls_back_to_the_system_and_is_retried_later(cache, monkeypatch):
    calls = []

    def build(dest, source=None, target="native"):
        calls.append(dest)
        raise S.SundialsNotFound("no compiler today")

    monkeypatch.setattr(S, "build", build)
    with pytest.warns(RuntimeWarning, match="no compiler today"):
        s = S.find_sundials()
    assert s.origin == "system"
    marker = cache / "sundials-cmake.failed"
    assert "no compiler today" in marker.read_text()
    assert S.find_sundials().origin == "system"
    assert len(calls) == 1  # not retried at once
    old = time.time() - S.RETRY_AFTER - 10
    os.utime(marker, (old, old))
    with pytest.warns(RuntimeWarning):
        S.find_sundials()
    assert len(calls) == 2


def test_no_sundials_anywhere_is_a_clear_error(cache, monkeypatch):
    monkeypatch.setattr(S, "_system", lambda: None)
    monkeypatch.setattr(S, "build", lambda *a, **k: (_ for _ in ()).throw(S.SundialsNotFound("offline")))
    with pytest.warns(RuntimeWarning), pytest.raises(S.SundialsNotFound, match="offline.*setup.sh"):
        S.find_sundials()


def test_build_can_be_switched_off(cache, monkeypatch):
    monkeypatch.setenv("PDBFS_SUNDIALS_BUILD", "0")
    monkeypatch.setattr(S, "build", lambda *a, **k: pytest.fail("built"))
    assert S.find_sundials().origin == "system"


def test_env_overrides_everything(cache, monkeypatch, tmp_path):
    monkeypatch.setenv("PDBFS_SUNDIALS_DIR", str(fake_prefix(tmp_path / "mine")))
    assert S.find_sundials().include_dir == tmp_path / "mine" / "include"
    monkeypatch.setenv("PDBFS_SUNDIALS_DIR", str(fake_prefix(tmp_path / "seven", "7.1.1")))
    with pytest.raises(S.SundialsNotFound, match="6.x"):
        S.find_sundials()


def test_the_build_script_is_sundials_own_cmake():
    text = S.BUILD_SCRIPT.read_text()
    assert "cmake -S" in text and "cmake --build" in text and "cmake --install" in text
    r = subprocess.run(["bash", "-n", str(S.BUILD_SCRIPT)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_the_binaries_link_the_cmake_build_when_there_is_one():
    """FMUs and the compiled backend are built with the SUNDIALS find_sundials
    picks; on a machine where the build works that is the CMake one, -O2."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        s = S.find_sundials()  # as export_fmu does: builds it if needed
    if S.failed_marker().exists():
        pytest.fail(f"the SUNDIALS build failed here: {S.failed_marker().read_text().strip()}")
    if os.environ.get("PDBFS_SUNDIALS_DIR") or os.environ.get("PDBFS_SUNDIALS_BUILD") == "0":
        pytest.skip("SUNDIALS chosen by the environment")
    assert s.include_dir == S.opt_cache_dir() / "include", s.origin
    assert s.version.startswith("6.")
    assert "CMake" in (S.opt_cache_dir() / "ORIGIN").read_text()
