"""pdbfs.fmu.sundials: search order, the optimised build and its fallback
(offline: the build is replaced by a stub, the caches by fake prefixes)."""
import os
import time
import warnings

import pytest

from pdbfs.fmu import sundials as S


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
    fake_prefix(tmp_path / "pdbfs" / "sundials")  # Debian's archives, already unpacked
    return tmp_path / "pdbfs"


def test_optimised_build_is_preferred_and_built_once(cache, monkeypatch):
    calls = []

    def build(dest, tarball=None, jobs=None):
        calls.append(dest)
        return fake_prefix(dest)

    monkeypatch.setattr(S, "build_optimised", build)
    for _ in range(2):
        s = S.find_sundials()
        assert s.include_dir == cache / "sundials-opt" / "include" and "-O2" in s.origin
    assert calls == [cache / "sundials-opt"]
    # without fetching, an existing build is still used
    assert S.find_sundials(fetch=False).include_dir == cache / "sundials-opt" / "include"


def test_failed_build_falls_back_to_debian_and_is_retried_later(cache, monkeypatch):
    calls = []

    def build(dest, tarball=None, jobs=None):
        calls.append(dest)
        raise S.SundialsNotFound("no compiler today")

    monkeypatch.setattr(S, "build_optimised", build)
    with pytest.warns(RuntimeWarning, match="no compiler today"):
        s = S.find_sundials()
    assert s.include_dir == cache / "sundials" / "include"
    marker = cache / "sundials-opt.failed"
    assert "no compiler today" in marker.read_text()
    assert S.find_sundials().include_dir == cache / "sundials" / "include"
    assert len(calls) == 1  # not retried at once
    old = time.time() - S.RETRY_AFTER - 10
    os.utime(marker, (old, old))
    with pytest.warns(RuntimeWarning):
        S.find_sundials()
    assert len(calls) == 2


def test_build_can_be_switched_off(cache, monkeypatch):
    monkeypatch.setenv("PDBFS_SUNDIALS_BUILD", "0")
    monkeypatch.setattr(S, "build_optimised", lambda *a, **k: pytest.fail("built"))
    assert S.find_sundials().include_dir == cache / "sundials" / "include"


def test_env_overrides_everything(cache, monkeypatch, tmp_path):
    monkeypatch.setenv("PDBFS_SUNDIALS_DIR", str(fake_prefix(tmp_path / "mine")))
    assert S.find_sundials().include_dir == tmp_path / "mine" / "include"
    monkeypatch.setenv("PDBFS_SUNDIALS_DIR", str(fake_prefix(tmp_path / "seven", "7.1.1")))
    with pytest.raises(S.SundialsNotFound, match="6.x"):
        S.find_sundials()


def test_configure_h():
    template = ("#cmakedefine A\n#cmakedefine B \"@X@\"\n#cmakedefine01 C\n#cmakedefine01 D\n"
                "#define V @V@\n@BLOCK@\n")
    out = S._configure_h(template, {"X": "x", "V": "6", "BLOCK": "#define E 1"}, {"B", "C"})
    assert out.splitlines() == ["/* #undef A */", '#define B "x"', "#define C 1", "#define D 0",
                                "#define V 6", "#define E 1"]


def test_the_fmu_links_an_optimised_sundials_when_there_is_one():
    """The FMU tests' binary is built with the SUNDIALS find_sundials picks;
    on a machine where the build works that is the -O2 one."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        s = S.find_sundials()  # as export_fmu does: builds it if needed
    if S._failure_marker().exists():
        pytest.skip(f"the optimised build failed here: {S._failure_marker().read_text().strip()}")
    if os.environ.get("PDBFS_SUNDIALS_DIR") or os.environ.get("PDBFS_SUNDIALS_BUILD") == "0":
        pytest.skip("SUNDIALS chosen by the environment")
    assert s.include_dir == S.opt_cache_dir() / "include", s.origin
    assert s.version.startswith("6.")
