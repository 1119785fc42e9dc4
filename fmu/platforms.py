"""The platforms an FMU's binaries are built for, and the build of one binary.

    linux64   the host's C compiler ($CC, default gcc): <id>.so
    win64     Debian's MinGW-w64 cross compiler (x86_64-w64-mingw32-gcc,
              package gcc-mingw-w64-x86-64): <id>.dll, statically linked
              (CVODE, libgcc and the C runtime's helpers inside: it needs
              only Windows' own DLLs)

Each binary links a static CVODE built for its platform with SUNDIALS' CMake
(``pdbfs.native.sundials.find_sundials(target=...)``). :func:`build_binary`
takes any list of C sources, so every FMI wrapper builds through it.
"""
from __future__ import annotations

import shutil
from dataclasses import dataclass
from pathlib import Path

from pdbfs.errors import ExportError
from pdbfs.native.codegen import CFLAGS, LDFLAGS, compiler, run_compiler
from pdbfs.native.sundials import Sundials, SundialsNotFound, find_sundials


class PlatformError(ExportError):
    """An unknown platform, or one this machine cannot build."""


@dataclass(frozen=True)
class Platform:
    name: str            # FMI 2.0 folder under binaries/
    fmi3_name: str       # FMI 3.0 platform tuple
    suffix: str          # of the shared library
    cc: str | None       # cross compiler; None: the host's ($CC)
    package: str | None  # the Debian package that brings cc
    sundials_target: str
    cflags: tuple[str, ...]
    ldflags: tuple[str, ...]


PLATFORMS = {
    "linux64": Platform("linux64", "x86_64-linux", ".so", None, None, "native", tuple(CFLAGS),
                        tuple(LDFLAGS)),
    "win64": Platform("win64", "x86_64-windows", ".dll", "x86_64-w64-mingw32-gcc", "gcc-mingw-w64-x86-64",
                      "win64", ("-std=gnu99", "-O2", "-shared", "-fno-math-errno"),
                      ("-static", "-static-libgcc", "-lm", "-Wl,--no-undefined")),
}


def can_build(name: str) -> bool:
    """Whether this machine has the compiler for platform ``name``."""
    p = PLATFORMS[name]
    return p.cc is None or shutil.which(p.cc) is not None


def default_platforms() -> list[str]:
    """Every platform this machine can build: linux64, and win64 when the
    MinGW-w64 cross compiler is there."""
    return [n for n in PLATFORMS if can_build(n)]


def resolve_platforms(platforms) -> list[str]:
    """The platform names to build, checked: ``None`` is the default set; a
    string may list several, comma separated. Raises PlatformError (one
    line) for an unknown name or a missing cross compiler."""
    if platforms is None:
        return default_platforms()
    if isinstance(platforms, str):
        platforms = platforms.split(",")
    names = [str(p).strip() for p in platforms]
    if not names or any(not n for n in names):
        raise PlatformError(f"platforms: empty name in {','.join(names)!r} (known: {', '.join(PLATFORMS)})")
    for n in names:
        if n not in PLATFORMS:
            raise PlatformError(f"unknown platform '{n}' (known: {', '.join(PLATFORMS)})")
        p = PLATFORMS[n]
        if not can_build(n):
            raise PlatformError(f"platform {n}: the cross compiler {p.cc} is not installed "
                                f"(Debian package {p.package}: apt-get install {p.package})")
    return list(dict.fromkeys(names))


def platform_sundials(name: str) -> Sundials:
    """The static CVODE for platform ``name`` (built once if needed)."""
    p = PLATFORMS[name]
    try:
        return find_sundials(target=p.sundials_target)
    except SundialsNotFound as err:
        raise ExportError(f"platform {name}: {err}") from err


def build_binary(name: str, sources: list[Path], include_dirs: list[Path], out: Path, what: str,
                 cflags: list[str] | None = None, sd: Sundials | None = None) -> Path:
    """Compile ``sources`` into the shared library ``out`` for platform
    ``name``, linked with that platform's static CVODE."""
    p = PLATFORMS[name]
    sd = sd or platform_sundials(name)
    cc = p.cc or compiler()
    cmd = [cc, *p.cflags, *(cflags or []), *[f"-I{d}" for d in include_dirs], f"-I{sd.include_dir}",
           *map(str, sources), "-o", str(out), *sd.link_args(), *p.ldflags]
    run_compiler(cmd, f"{what} for {name}")
    return out
