"""Locate the static SUNDIALS/CVODE that FMU binaries and the compiled backend
link; build it once if there is none.

Search order of :func:`find_sundials`:

1. ``$PDBFS_SUNDIALS_DIR``: an install prefix of SUNDIALS 6.x with
   ``include/cvode/cvode.h`` and ``lib/libsundials_cvode.a`` (static,
   position independent).
2. The build in the cache, ``$XDG_CACHE_HOME/pdbfs/sundials-cmake`` (default
   ``~/.cache/pdbfs/sundials-cmake``), made once by ``build_sundials.sh``:
   SUNDIALS' own CMake, -O2, from Debian's source of the ``sundials``
   package (``$PDBFS_SUNDIALS_SOURCE`` names a local source tarball instead).
   A failed build warns, leaves its reason in ``sundials-cmake.failed`` beside
   the cache and is retried a day later (or once that file is deleted).
3. The system's SUNDIALS (Debian's ``libsundials-dev``). Its archives are
   compiled without optimisation: CVODE runs about 3-4x slower with them
   (paper rig, one fmi2DoStep over 20 ms: 3.4 ms against 1.1 ms), which is
   why pdbfs builds its own.

``PDBFS_SUNDIALS_BUILD=0`` switches the build off (an existing one is used).

Other targets (``find_sundials(target=...)``), each cached beside the native
build and built once by the same script from the same source: ``"win64"``, a
CVODE cross-compiled for 64-bit Windows with Debian's MinGW-w64
(``sundials-cmake-win64``; no system fallback), and ``"sources"``, no build
but the C sources and headers that CVODE is compiled from, with SUNDIALS'
LICENSE (``sundials-src``, for source FMUs).
"""
from __future__ import annotations

import os
import platform
import subprocess
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import platformdirs

from pdbfs.errors import ExportError

BUILD_SCRIPT = Path(__file__).with_name("build_sundials.sh")
#: link order; a CMake build puts everything CVODE needs into the first one
_ARCHIVES = ["libsundials_cvode.a", "libsundials_nvecserial.a", "libsundials_sunmatrixdense.a",
             "libsundials_sunmatrixband.a", "libsundials_sunlinsoldense.a",
             "libsundials_sunlinsolband.a", "libsundials_sunnonlinsolfixedpoint.a",
             "libsundials_sunnonlinsolnewton.a", "libsundials_generic.a"]
#: a failed build is retried after this many seconds (or when the marker is deleted)
RETRY_AFTER = 24 * 3600


class SundialsNotFound(RuntimeError):
    pass


@dataclass(frozen=True)
class Sundials:
    include_dir: Path
    libraries: tuple[Path, ...]   # static archives, in link order
    version: str
    origin: str

    def link_args(self) -> list[str]:
        return [str(p) for p in self.libraries]


def cache_root() -> Path:
    """pdbfs's cache folder: ``$XDG_CACHE_HOME/pdbfs`` (default ``~/.cache/pdbfs``),
    made if need be; one that cannot be made is an ExportError naming the folder
    and the variable it came from."""
    root = Path(platformdirs.user_cache_dir("pdbfs", appauthor=False))
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        origin = "$XDG_CACHE_HOME" if os.environ.get("XDG_CACHE_HOME") else "$HOME/.cache"
        raise ExportError(f"cannot make pdbfs's cache folder {root} (from {origin}): "
                          f"{err.strerror or err}; point XDG_CACHE_HOME at a writable folder") \
            from None
    return root


#: cache folder of each target's build, under cache_root()
TARGET_DIRS = {"native": "sundials-cmake", "win64": "sundials-cmake-win64", "sources": "sundials-src"}


def opt_cache_dir(target: str = "native") -> Path:
    return cache_root() / TARGET_DIRS[target]


def failed_marker(target: str = "native") -> Path:
    return cache_root() / (TARGET_DIRS[target] + ".failed")


def _version(include_dir: Path) -> str:
    try:
        for line in (include_dir / "sundials" / "sundials_config.h").read_text().splitlines():
            if line.startswith("#define SUNDIALS_VERSION "):
                return line.split('"')[1]
    except OSError:
        pass
    return "unknown"


def from_prefix(prefix: Path, origin: str) -> Sundials | None:
    """The SUNDIALS installed under ``prefix``, or None if there is none."""
    inc = prefix / "include"
    for libdir in (prefix / "lib", prefix / "lib64", prefix / "lib" / f"{platform.machine()}-linux-gnu"):
        if (inc / "cvode" / "cvode.h").is_file() and (libdir / "libsundials_cvode.a").is_file():
            version = _version(inc)
            if not version.startswith("6."):
                raise SundialsNotFound(f"SUNDIALS in {prefix} is version {version}; pdbfs's C "
                                       "drivers need the 6.x API")
            return Sundials(inc, tuple(libdir / a for a in _ARCHIVES if (libdir / a).is_file()),
                            version, origin)
    return None


def build(prefix: Path, source: str | None = None, target: str = "native") -> Path:
    """Run ``build_sundials.sh`` into ``prefix`` (about 10 s on two cores)."""
    cmd = ["bash", str(BUILD_SCRIPT), str(prefix)] + ([source] if source else [])
    r = subprocess.run(cmd, capture_output=True, text=True,
                       env={**os.environ, "PDBFS_SUNDIALS_TARGET": target})
    if r.returncode != 0:
        raise SundialsNotFound(f"building SUNDIALS failed: {(r.stderr or r.stdout).strip()[-1500:]}")
    return prefix


def _recent_failure(marker: Path) -> bool:
    try:
        return time.time() - marker.stat().st_mtime < RETRY_AFTER
    except OSError:
        return False


def _cached(fetch: bool, target: str = "native") -> Sundials | None:
    """The cached build, building it first if needed and allowed."""
    dest = opt_cache_dir(target)
    origin = f"{dest} (built with SUNDIALS' CMake, -O2)"
    s = from_prefix(dest, origin)
    if s is not None or not fetch or os.environ.get("PDBFS_SUNDIALS_BUILD", "1") in ("0", "no", "false"):
        return s
    marker = failed_marker(target)
    if _recent_failure(marker):
        return None
    import fcntl
    dest.parent.mkdir(parents=True, exist_ok=True)
    with open(dest.parent / f".{dest.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)   # one build at a time; the others wait and reuse it
        try:
            s = from_prefix(dest, origin)
            if s is None and not _recent_failure(marker):
                build(dest, os.environ.get("PDBFS_SUNDIALS_SOURCE"), target)
                s = from_prefix(dest, origin)
        except Exception as err:   # noqa: BLE001 - any failure: fall back to the system's
            marker.write_text(f"{type(err).__name__}: {err}\n")
            warnings.warn(f"could not build SUNDIALS ({err}); looking for the system's "
                          f"(delete {marker} to retry)", RuntimeWarning, stacklevel=3)
            return None
    return s


def _system() -> Sundials | None:
    return from_prefix(Path("/usr"), "system (Debian libsundials-dev, unoptimised)")


def find_sundials(fetch: bool = True, target: str = "native") -> Sundials:
    """The SUNDIALS to link: ``$PDBFS_SUNDIALS_DIR``, else the cached build
    (built once if ``fetch``), else the system's. ``target="win64"``: the
    cached MinGW-w64 build only."""
    if target != "native":
        return _other_target(fetch, target)
    env = os.environ.get("PDBFS_SUNDIALS_DIR")
    if env:
        s = from_prefix(Path(env), f"PDBFS_SUNDIALS_DIR={env}")
        if s is None:
            raise SundialsNotFound(f"PDBFS_SUNDIALS_DIR={env} has no include/cvode/cvode.h and "
                                   "lib/libsundials_cvode.a")
        return s
    s = _cached(fetch) or _system()
    if s is None:
        why = failed_marker().read_text().strip() if failed_marker().exists() else \
            "the build is switched off" if not fetch else "no build was attempted"
        raise SundialsNotFound(
            f"no SUNDIALS 6.x static archives: not in $PDBFS_SUNDIALS_DIR, {opt_cache_dir()} or "
            f"the system ({why}). Run scripts/setup.sh, or install libsundials-dev")
    return s


def _other_target(fetch: bool, target: str) -> Sundials:
    if target not in TARGET_DIRS or target == "sources":
        raise SundialsNotFound(f"unknown SUNDIALS target '{target}' (known: native, win64)")
    s = _cached(fetch, target)
    if s is None:
        marker = failed_marker(target)
        why = marker.read_text().strip() if marker.exists() else "the build is switched off"
        raise SundialsNotFound(f"no SUNDIALS for {target} in {opt_cache_dir(target)} ({why})")
    return s


@dataclass(frozen=True)
class SundialsSources:
    """SUNDIALS' C sources (``src``: cvode/, sundials/, ...), public headers
    (``include``) and LICENSE, from the source the builds use."""
    root: Path
    origin: str

    @property
    def src(self) -> Path:
        return self.root / "src"

    @property
    def include(self) -> Path:
        return self.root / "include"

    @property
    def license(self) -> Path:
        return self.root / "LICENSE"


def find_sundials_sources(fetch: bool = True) -> SundialsSources:
    """The cached SUNDIALS sources (``sundials-src``), extracted once from the
    source the builds use."""
    dest = opt_cache_dir("sources")

    def ready() -> bool:
        return (dest / "src" / "cvode" / "cvode.c").is_file() and (dest / "LICENSE").is_file()
    if not ready() and fetch and os.environ.get("PDBFS_SUNDIALS_BUILD", "1") not in ("0", "no", "false") \
            and not _recent_failure(failed_marker("sources")):
        import fcntl
        dest.parent.mkdir(parents=True, exist_ok=True)
        with open(dest.parent / f".{dest.name}.lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                if not ready():
                    build(dest, os.environ.get("PDBFS_SUNDIALS_SOURCE"), "sources")
            except SundialsNotFound as err:
                failed_marker("sources").write_text(f"{err}\n")
    if not ready():
        raise SundialsNotFound(f"no SUNDIALS sources in {dest}")
    origin = (dest / "ORIGIN").read_text().strip() if (dest / "ORIGIN").is_file() else str(dest)
    return SundialsSources(dest, origin)
