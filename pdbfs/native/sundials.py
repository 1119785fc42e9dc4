"""SUNDIALS' CVODE for every binary pdbfs builds, from a PyPI distribution.

The sources are SUNDIALS 7.1.1 as carried by the source distribution
``amici-1.1.0.tar.gz`` on PyPI (pinned by SHA-256 below): its CVODES (a
superset of CVODE with the same ``CVode*`` calls), the serial vector, the
dense and band matrices and linear solvers, Newton and fixed point and the
generic layer, with SUNDIALS' LICENSE (BSD-3-Clause). The repository holds
no SUNDIALS code.

* :func:`find_sundials_sources` fetches the sdist once per machine into the
  cache (``$XDG_CACHE_HOME/pdbfs/sundials-7.1.1``, default
  ``~/.cache/pdbfs``) the way pip finds packages (``pipindex.py``: the
  index and find-links pip is configured with, within 20 s), checks its hash,
  keeps it (``sdist/``, to carry to an offline machine) and extracts only
  those files, with a ``sundials_config.h`` and ``sundials_export.h`` that
  pdbfs writes (no CMake). ``$PDBFS_SUNDIALS_SDIST`` names a local copy of
  the sdist instead (offline machines). A fetch that failed is remembered in
  the cache for :data:`REMEMBER` s (for the same index settings), so that a
  caller with a fallback (:func:`remembered_failures`: backend "auto") falls
  back at once rather than waiting for a dead index again.
* :func:`find_sundials` compiles :data:`SUNDIALS_C` once per target with
  the target's compiler (``toolchain.py``: ``zig cc -O2``) into a static
  archive in the cache, under a file lock (any OS), and returns it, saying
  on stderr how far it is (``[3/31] compiling cvodes_ls.c for aarch64-linux``).
"""
from __future__ import annotations

import contextvars
import hashlib
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from pdbfs.errors import ExportError
from pdbfs.files import cache_folder

from . import toolchain
from .sundials_config import CONFIG_H, EXPORT_H

VERSION = "7.1.1"
PROJECT = "amici"
SDIST = "amici-1.1.0.tar.gz"
SDIST_SHA256 = "63d51cbbf1f989f2f852bb98c9b5a59501f4d3697883221737ff0188eec6870f"
#: how to get the sdist by hand on a machine with pip (any Python: the sdist
#: itself declares Requires-Python >= 3.12, which --python-version answers)
PIP_DOWNLOAD = (f"pip download --no-deps --no-binary {PROJECT} --python-version 3.12 "
                f"{PROJECT}==1.1.0")
#: SUNDIALS' folder inside the sdist
SDIST_ROOT = "amici-1.1.0/amici/_installation/ThirdParty/sundials/"

#: SUNDIALS' C files the CVODE loop links, relative to src/
SUNDIALS_C = (
    "cvodes/cvodes.c", "cvodes/cvodes_io.c", "cvodes/cvodes_ls.c", "cvodes/cvodes_nls.c",
    "cvodes/cvodes_nls_sim.c", "cvodes/cvodes_nls_stg.c", "cvodes/cvodes_nls_stg1.c",
    "cvodes/cvodes_proj.c", "cvodes/cvodea.c", "cvodes/cvodea_io.c",
    "nvector/serial/nvector_serial.c",
    "sunmatrix/dense/sunmatrix_dense.c", "sunmatrix/band/sunmatrix_band.c",
    "sunlinsol/dense/sunlinsol_dense.c", "sunlinsol/band/sunlinsol_band.c",
    "sunnonlinsol/newton/sunnonlinsol_newton.c", "sunnonlinsol/fixedpoint/sunnonlinsol_fixedpoint.c",
    "sundials/sundials_band.c", "sundials/sundials_context.c", "sundials/sundials_dense.c",
    "sundials/sundials_errors.c", "sundials/sundials_futils.c", "sundials/sundials_hashmap.c",
    "sundials/sundials_linearsolver.c", "sundials/sundials_logger.c", "sundials/sundials_math.c",
    "sundials/sundials_matrix.c", "sundials/sundials_nonlinearsolver.c", "sundials/sundials_nvector.c",
    "sundials/sundials_nvector_senswrapper.c", "sundials/sundials_version.c",
)
#: what is extracted: the C files' folders (their internal headers), the public headers, the licence
_EXTRACT = tuple(sorted({"src/" + c.rsplit("/", 1)[0] + "/" for c in SUNDIALS_C})) + (
    "include/cvodes/", "include/nvector/", "include/sundials/", "include/sunmatrix/",
    "include/sunlinsol/", "include/sunnonlinsol/", "include/sunmemory/", "LICENSE")


class SundialsNotFound(RuntimeError):
    """SUNDIALS' sources could not be had (not downloadable, a wrong hash, an
    unreadable file). ``short``: why, in a few words, for a one-line warning."""

    def __init__(self, message: str, short: str = ""):
        super().__init__(message)
        self.short = short


@dataclass(frozen=True)
class SundialsSources:
    """SUNDIALS' C sources (``src``), public headers with pdbfs's config
    (``include``) and LICENSE, extracted from the pinned sdist."""
    root: Path
    origin: str
    version: str = VERSION

    @property
    def src(self) -> Path:
        """The folder of SUNDIALS' C sources."""
        return self.root / "src"

    @property
    def include(self) -> Path:
        """The folder of the public headers, pdbfs's configuration headers included."""
        return self.root / "include"

    @property
    def license(self) -> Path:
        """SUNDIALS' LICENSE file."""
        return self.root / "LICENSE"


@dataclass(frozen=True)
class Sundials:
    """A static CVODE built for one target."""
    include_dir: Path
    libraries: tuple[Path, ...]
    version: str
    origin: str
    target: str = ""

    def link_args(self) -> list[str]:
        """The static libraries to put on a link line."""
        return [str(p) for p in self.libraries]


def cache_root() -> Path:
    """pdbfs's cache folder: ``$XDG_CACHE_HOME/pdbfs`` (default ``~/.cache/pdbfs``),
    made if need be; one that cannot be made is an ExportError naming the folder
    and the variable it came from."""
    root = cache_folder()
    try:
        root.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        origin = "$XDG_CACHE_HOME" if os.environ.get("XDG_CACHE_HOME") else "the home folder"
        raise ExportError(f"cannot make pdbfs's cache folder {root} (from {origin}): "
                          f"{err.strerror or err}; point XDG_CACHE_HOME at a writable folder") \
            from None
    return root


def _say(msg: str) -> None:
    print(f"pdbfs: {msg}", file=sys.stderr, flush=True)


def sdist_path() -> Path:
    """Where the cache keeps the sdist once fetched (to carry to an offline machine)."""
    return cache_root() / "sdist" / SDIST


#: seconds a failed fetch of the sources is remembered (for the same index settings)
REMEMBER = 600.0
#: whether a fetch that failed within REMEMBER s is taken as failing again at once
_TRUST_MEMO: contextvars.ContextVar[bool] = contextvars.ContextVar("pdbfs_sundials_memo",
                                                                   default=False)


@contextmanager
def remembered_failures():
    """Within this block a fetch of the sources that failed less than
    :data:`REMEMBER` s ago, with the same index settings, fails again at once
    (SundialsNotFound saying when and why) instead of waiting for the index:
    for a caller with a fallback (backend "auto"). Outside it, a fetch always
    asks the index again (``pdbfs prepare-offline``, ``backend="c"``)."""
    token = _TRUST_MEMO.set(True)
    try:
        yield
    finally:
        _TRUST_MEMO.reset(token)


def _span(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else f"{seconds / 60:.0f} min"


def _memo_path() -> Path:
    return cache_root() / "sundials-fetch-failed.json"


def _remembered(key: str) -> tuple[float, str] | None:
    """(seconds ago, short reason) of a failed fetch with index settings
    ``key`` less than REMEMBER s ago, else None."""
    try:
        memo = json.loads(_memo_path().read_text())
        ago = time.time() - float(memo["at"])
        if memo["key"] == key and 0 <= ago < REMEMBER:
            return ago, str(memo["short"])
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return None


def _remember(key: str | None, short: str = "") -> None:
    """Keep a failed fetch (``key``: its index settings) or, with None, forget it."""
    path = _memo_path()
    try:
        if key is None:
            path.unlink(missing_ok=True)
            return
        part = path.with_name(f".{path.name}.{os.getpid()}")
        part.write_text(json.dumps({"key": key, "at": time.time(), "short": short}))
        os.replace(part, path)
    except OSError:
        pass                       # a cache that cannot be written: every command asks again


def _download() -> bytes:
    local = os.environ.get("PDBFS_SUNDIALS_SDIST")
    if local:
        try:
            return Path(local).read_bytes()
        except OSError as err:
            raise SundialsNotFound(f"PDBFS_SUNDIALS_SDIST={local}: {err.strerror or err}") from None
    kept = sdist_path()
    if kept.is_file():
        return kept.read_bytes()
    from . import pipindex       # urllib and its kin: only where the network is asked
    settings = pipindex.pip_settings()
    key = settings.key()
    failed = _remembered(key) if _TRUST_MEMO.get() else None
    if failed is not None:
        ago, short = failed
        raise SundialsNotFound(
            f"SUNDIALS' sources ({SDIST}) could not be fetched {_span(ago)} ago ({short}); "
            f"not asked again for {_span(REMEMBER - ago)} (`pdbfs prepare-offline` tries now)",
            f"{short} {_span(ago)} ago")
    _say(f"fetching SUNDIALS {VERSION}'s sources once: {SDIST} (1.3 MB) from the package "
         "index pip uses")
    try:
        data, origin = pipindex.fetch(PROJECT, SDIST, SDIST_SHA256, settings=settings)
    except pipindex.FetchError as err:
        short = "package index unreachable" if err.unreachable else \
            f"no {SDIST} with the pinned hash on the package index"
        _remember(key, short)
        raise SundialsNotFound(
            f"could not fetch SUNDIALS' sources ({SDIST}) through pip's index: {err}. On a "
            f"machine with access run `pdbfs prepare-offline`, or get the file with `"
            f"{PIP_DOWNLOAD}` and set PDBFS_SUNDIALS_SDIST to its path", short) from None
    _remember(None)
    _say(f"fetched {SDIST} from {origin}")
    try:
        kept.parent.mkdir(parents=True, exist_ok=True)
        part = kept.with_name(f".{SDIST}.{os.getpid()}")
        part.write_bytes(data)
        os.replace(part, kept)
    except OSError:
        pass               # not kept: the sources are extracted all the same
    return data


def _extract(data: bytes, dest: Path) -> None:
    digest = hashlib.sha256(data).hexdigest()
    if digest != SDIST_SHA256:
        raise SundialsNotFound(f"{SDIST} has SHA-256 {digest}, not the pinned {SDIST_SHA256}")
    part = Path(tempfile.mkdtemp(prefix=dest.name + ".", dir=dest.parent))
    try:
        import tarfile
        with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
            for m in tar.getmembers():
                rel = m.name[len(SDIST_ROOT):] if m.name.startswith(SDIST_ROOT) else None
                if not m.isfile() or rel is None or not rel.startswith(_EXTRACT):
                    continue
                if not (rel.endswith((".c", ".h")) or rel == "LICENSE") or ".." in rel.split("/"):
                    continue
                out = part / rel
                out.parent.mkdir(parents=True, exist_ok=True)
                out.write_bytes(tar.extractfile(m).read())
        (part / "include" / "sundials" / "sundials_config.h").write_text(CONFIG_H)
        (part / "include" / "sundials" / "sundials_export.h").write_text(EXPORT_H)
        (part / "ORIGIN").write_text(f"SUNDIALS {VERSION} from {SDIST} (sha256 {SDIST_SHA256})\n")
        if dest.exists():
            shutil.rmtree(dest)
        os.replace(part, dest)
    finally:
        shutil.rmtree(part, ignore_errors=True)


def cache_lock(path: Path):
    """A FileLock beside ``path`` (a file or folder of the cache), for the
    process that builds it: another one waits, then finds it built."""
    from filelock import FileLock
    path.parent.mkdir(parents=True, exist_ok=True)
    return FileLock(str(path.parent / f".{path.name}.lock"))


def check_sdist_variable() -> None:
    """``$PDBFS_SUNDIALS_SDIST``, where set, names the pinned sdist: a
    missing or other file is a SundialsNotFound naming the variable (asked
    before work that means to use it: the cache may not need it)."""
    local = os.environ.get("PDBFS_SUNDIALS_SDIST")
    if not local:
        return
    where, path = f"PDBFS_SUNDIALS_SDIST={local}", Path(local)
    if not path.is_file():
        raise SundialsNotFound(f"{where}: " + ("is a folder" if path.is_dir() else "no such file")
                               + f"; name the file {SDIST}, or unset the variable")
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError as err:
        raise SundialsNotFound(f"{where}: {err.strerror or err}") from None
    if digest != SDIST_SHA256:
        raise SundialsNotFound(f"{where}: not {SDIST} (its SHA-256 is {digest[:16]}..., the "
                               f"pinned one's {SDIST_SHA256[:16]}...)")


def find_sundials_sources(fetch: bool = True) -> SundialsSources:
    """SUNDIALS' sources in the cache, fetched and extracted once."""
    dest = cache_root() / f"sundials-{VERSION}"

    def ready() -> bool:
        return (dest / "ORIGIN").is_file()
    if not ready():
        if not fetch:
            raise SundialsNotFound(f"no SUNDIALS sources in {dest}")
        with cache_lock(dest):
            if not ready():
                _extract(_download(), dest)
    return SundialsSources(dest, (dest / "ORIGIN").read_text().strip())


def _compile_all(cmd: list[str], sources: SundialsSources, objdir: Path,
                 target: str = "") -> list[Path]:
    done = [0]
    lock = threading.Lock()
    env = toolchain.zig_env()

    def one(rel: str) -> Path:
        obj = objdir / (Path(rel).stem + ".o")
        r = subprocess.run([*cmd, "-c", f"-I{sources.include}", f"-I{sources.src / 'sundials'}", str(sources.src / rel), "-o", str(obj)],
                           capture_output=True, text=True, env=env)
        if r.returncode != 0:
            raise SundialsNotFound(f"compiling SUNDIALS' {rel} with {Path(cmd[0]).name} failed: "
                                   f"{toolchain.first_error(r.stderr)}")
        with lock:                 # each step as it ends, with its share of the whole
            done[0] += 1
            _say(f"[{done[0]}/{len(SUNDIALS_C)}] compiled {Path(rel).name} for {target}")
        return obj
    from concurrent.futures import ThreadPoolExecutor
    with ThreadPoolExecutor(max_workers=max(1, min(4, os.cpu_count() or 1))) as pool:
        return list(pool.map(one, SUNDIALS_C))


def find_sundials(fetch: bool = True, target: str | None = None) -> Sundials:
    """The static CVODE for ``target`` (default: the host's), compiled once
    into the cache with that target's compiler."""
    target = target or toolchain.host_target()
    sources = find_sundials_sources(fetch)
    cmd = [*toolchain.compiler(target), *toolchain.cflags(target), "-DNDEBUG"]
    key = hashlib.sha256("\0".join([VERSION, target, *(Path(c).name for c in cmd)]).encode())
    dest = cache_root() / f"cvode-{VERSION}" / f"{target}-{key.hexdigest()[:12]}"
    lib = dest / "libsundials_cvodes.a"
    origin = f"SUNDIALS {VERSION} CVODES from {SDIST}, {' '.join(Path(c).name for c in cmd)}"
    if not lib.is_file():
        if not fetch:
            raise SundialsNotFound(f"no CVODE built for {target} in {dest}")
        with cache_lock(dest):
            if not lib.is_file():
                _say(f"compiling CVODE for {target} once ({len(SUNDIALS_C)} files, about a minute)")
                dest.mkdir(parents=True, exist_ok=True)
                with tempfile.TemporaryDirectory(dir=dest) as tmp:
                    objs = _compile_all(cmd, sources, Path(tmp), target)
                    part = Path(tmp) / lib.name
                    r = subprocess.run([*toolchain.archiver(), "rcs", str(part), *map(str, objs)],
                                       capture_output=True, text=True, env=toolchain.zig_env())
                    if r.returncode != 0:
                        raise SundialsNotFound(f"archiving CVODE failed: {toolchain.first_error(r.stderr)}")
                    os.replace(part, lib)
    return Sundials(sources.include, (lib,), VERSION, origin, target)
