"""Locate (and if needed fetch or build) the static SUNDIALS/CVODE archives
that the co-simulation binary of an exported FMU embeds.

Search order:

1. ``$PDBFS_SUNDIALS_DIR``: a directory with ``include/cvode/cvode.h`` and
   ``lib/libsundials_cvode.a`` (a CMake install prefix of SUNDIALS 6.x built
   with ``-DBUILD_STATIC_LIBS=ON -DCMAKE_POSITION_INDEPENDENT_CODE=ON``, or
   the layout this module writes).
2. an optimised build in the cache ``$XDG_CACHE_HOME/pdbfs/sundials-opt``
   (default ``~/.cache/pdbfs/sundials-opt``).  If it is missing, it is built
   once: Debian's source of the ``sundials`` package (the same 6.4.1 as
   ``libsundials-dev``) is downloaded with ``apt-get source`` (if a deb-src
   line is configured) or with apt's ``apt-helper`` from the pool directory
   of ``libsundials-dev`` (checked against a pinned SHA-256), and just the
   objects of CMake's ``libsundials_cvode.a`` (CVODE, generic code, serial
   N_Vector, matrices, linear and nonlinear solvers) are compiled with
   ``$CC -O2 -fPIC`` into that one archive and checked with a small CVODE
   program (about 10 s on two cores, download included).  If that fails,
   a warning is issued, the reason is written to ``sundials-opt.failed``
   beside the cache (the build is retried a day later, or at once when the
   file is deleted), and the search goes on:
3. Debian's unoptimised archives in ``$XDG_CACHE_HOME/pdbfs/sundials``.
4. the system, if Debian's ``libsundials-dev`` is installed.
5. Debian's ``libsundials-dev`` downloaded with ``apt-get download`` (no
   installation, no dependencies), its headers and static archives unpacked
   into ``$XDG_CACHE_HOME/pdbfs/sundials`` with ``dpkg-deb -x``.  Debian's
   archives are position independent (they link into a shared object) but
   compiled without optimisation: CVODE runs about 3-4x slower with them.

``PDBFS_SUNDIALS_BUILD=0`` skips step 2's build (an existing optimised build
is still used).
"""
from __future__ import annotations

import os
import platform
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

_ARCHIVES = ["libsundials_cvode.a", "libsundials_nvecserial.a", "libsundials_sunmatrixdense.a",
             "libsundials_sunlinsoldense.a", "libsundials_sunnonlinsolfixedpoint.a",
             "libsundials_sunnonlinsolnewton.a", "libsundials_generic.a"]
_HEADER_DIRS = ["cvode", "nvector", "sundials", "sunlinsol", "sunmatrix", "sunnonlinsol", "sunmemory"]
_HEADER_FILES = ["sundials_context_impl.h", "sundials_hashmap.h", "sundials_logger_impl.h"]


class SundialsNotFound(RuntimeError):
    pass


@dataclass(frozen=True)
class Sundials:
    include_dir: Path
    libraries: tuple[Path, ...]   # static archives, link in this order
    version: str
    origin: str

    def link_args(self) -> list[str]:
        return [str(p) for p in self.libraries]


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "pdbfs" / "sundials"


def _version(include_dir: Path) -> str:
    cfg = include_dir / "sundials" / "sundials_config.h"
    try:
        for line in cfg.read_text().splitlines():
            if line.startswith("#define SUNDIALS_VERSION "):
                return line.split('"')[1]
    except OSError:
        pass
    return "unknown"


def _from_prefix(prefix: Path, origin: str) -> Sundials | None:
    inc = prefix / "include"
    for libdir in (prefix / "lib", prefix / "lib64", prefix / "lib" / "x86_64-linux-gnu"):
        if (inc / "cvode" / "cvode.h").is_file() and (libdir / "libsundials_cvode.a").is_file():
            libs = tuple(libdir / a for a in _ARCHIVES if (libdir / a).is_file())
            version = _version(inc)
            if not version.startswith("6."):
                raise SundialsNotFound(f"SUNDIALS in {prefix} is version {version}; the FMU wrapper "
                                       "needs the 6.x API")
            return Sundials(inc, libs, version, origin)
    return None


def _system() -> Sundials | None:
    libdir = Path("/usr/lib") / f"{platform.machine()}-linux-gnu"
    if (Path("/usr/include/cvode/cvode.h").is_file() and (libdir / "libsundials_cvode.a").is_file()):
        libs = tuple(libdir / a for a in _ARCHIVES if (libdir / a).is_file())
        version = _version(Path("/usr/include"))
        if version.startswith("6."):
            return Sundials(Path("/usr/include"), libs, version, "system")
    return None


def fetch_debian(dest: Path) -> Path:
    """Download Debian's libsundials-dev with ``apt-get download`` and unpack
    its headers and static archives into ``dest`` (include/, lib/)."""
    for tool in ("apt-get", "dpkg-deb"):
        if shutil.which(tool) is None:
            raise SundialsNotFound(
                f"SUNDIALS static libraries not found and '{tool}' is not available to fetch them. "
                "Install SUNDIALS 6.x static archives (libsundials_cvode.a, position independent) and "
                "set PDBFS_SUNDIALS_DIR to their install prefix, or on Debian/Ubuntu run "
                "'apt-get install libsundials-dev'.")
    with tempfile.TemporaryDirectory(prefix="pdbfs-sundials-") as tmp:
        tmp = Path(tmp)
        os.chmod(tmp, 0o755)  # apt's sandbox user must be able to write here
        r = subprocess.run(["apt-get", "download", "libsundials-dev"], cwd=tmp, capture_output=True, text=True)
        debs = list(tmp.glob("libsundials-dev_*.deb"))
        if r.returncode != 0 or not debs:
            raise SundialsNotFound(
                "could not download Debian's libsundials-dev with 'apt-get download' "
                f"(exit {r.returncode}): {r.stderr.strip()[-500:]}\n"
                "Run 'apt-get update' first, or set PDBFS_SUNDIALS_DIR to a SUNDIALS 6.x install prefix "
                "with static, position-independent archives.")
        x = tmp / "x"
        subprocess.run(["dpkg-deb", "-x", str(debs[0]), str(x)], check=True, capture_output=True)
        srcinc = x / "usr" / "include"
        srclib = next((d for d in (x / "usr" / "lib").glob("*-linux-gnu")), x / "usr" / "lib")
        if not (srclib / "libsundials_cvode.a").is_file():
            raise SundialsNotFound(f"{debs[0].name} has no libsundials_cvode.a")
        stage = Path(tempfile.mkdtemp(prefix=".stage-", dir=_ensure(dest.parent)))
        (stage / "lib").mkdir()
        (stage / "include").mkdir()
        for a in _ARCHIVES:
            if (srclib / a).is_file():
                shutil.copy2(srclib / a, stage / "lib" / a)
        for d in _HEADER_DIRS:
            if (srcinc / d).is_dir():
                shutil.copytree(srcinc / d, stage / "include" / d)
        for f in _HEADER_FILES:
            if (srcinc / f).is_file():
                shutil.copy2(srcinc / f, stage / "include" / f)
        (stage / "ORIGIN").write_text(f"{debs[0].name}\n")
        if dest.exists():
            shutil.rmtree(stage)  # another process was faster
        else:
            os.replace(stage, dest)
    return dest


def _ensure(p: Path) -> Path:
    p.mkdir(parents=True, exist_ok=True)
    return p


# ------------------------------------------------------------ optimised build

#: Debian source tarballs compiled when they were downloaded without apt's
#: signature check (apt-helper, from libsundials-dev's pool directory):
#: file name -> SHA-256 (bookworm's sundials 6.4.1+dfsg1-3)
_PINNED_SOURCES = {
    "sundials_6.4.1+dfsg1.orig.tar.xz": "c61157f1d4be06c704bea40cb131eb63ba2dada161989071604d0a0959cdf04a",
}

#: the objects of SUNDIALS 6.4's libsundials_cvode (its CMakeLists: CVODE with
#: the generic code, system memory, serial N_Vector, band/dense/sparse matrices,
#: their direct and the iterative linear solvers, Newton and fixed-point
#: nonlinear solvers), all in one archive as CMake builds it; serial, double
#: precision, 64-bit indices, no MPI, no profiling, no Fortran
_CVODE_SOURCES = (
    [f"src/cvode/cvode{m}.c" for m in (
        "", "_bandpre", "_bbdpre", "_diag", "_direct", "_io", "_ls", "_nls", "_proj", "_spils")]
    + [f"src/sundials/sundials_{m}.c" for m in (
        "band", "context", "dense", "direct", "iterative", "linearsolver", "logger", "math", "matrix",
        "memory", "nonlinearsolver", "nvector", "nvector_senswrapper", "version", "futils")]
    + ["src/sunmemory/system/sundials_system_memory.c", "src/nvector/serial/nvector_serial.c"]
    + [f"src/sunmatrix/{m}/sunmatrix_{m}.c" for m in ("band", "dense", "sparse")]
    + [f"src/sunlinsol/{m}/sunlinsol_{m}.c" for m in ("band", "dense")]
    + [f"src/sunlinsol/{m}/sunlinsol_{m}.c" for m in ("spbcgs", "spfgmr", "spgmr", "sptfqmr", "pcg")]
    + [f"src/sunnonlinsol/{m}/sunnonlinsol_{m}.c" for m in ("newton", "fixedpoint")]
)
OPT_CFLAGS = ["-O2", "-fPIC", "-DNDEBUG", "-std=gnu99"]

_CONFIG_DEFINES = {"SUNDIALS_C_COMPILER_HAS_MATH_PRECISIONS", "SUNDIALS_C_COMPILER_HAS_ISINF_ISNAN",
                   "SUNDIALS_C_COMPILER_HAS_INLINE", "SUNDIALS_HAVE_POSIX_TIMERS",
                   "SUNDIALS_C_COMPILER_HAS_SNPRINTF_AND_VA_COPY"}

_EXPORT_H = """\
/* written by pdbfs.fmu.sundials: static archives, no symbol visibility control */
#ifndef SUNDIALS_EXPORT_H
#define SUNDIALS_EXPORT_H
#define SUNDIALS_EXPORT
#define SUNDIALS_NO_EXPORT
#define SUNDIALS_DEPRECATED __attribute__ ((__deprecated__))
#define SUNDIALS_DEPRECATED_EXPORT SUNDIALS_EXPORT SUNDIALS_DEPRECATED
#define SUNDIALS_DEPRECATED_NO_EXPORT SUNDIALS_NO_EXPORT SUNDIALS_DEPRECATED
#endif
"""

_SMOKE_TEST = r"""
#include <math.h>
#include <stdio.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
static int f(realtype t, N_Vector y, N_Vector dy, void *u) {
    (void)t; (void)u; NV_Ith_S(dy, 0) = NV_Ith_S(y, 1); NV_Ith_S(dy, 1) = -NV_Ith_S(y, 0); return 0;
}
static int run(int lmm) {
    SUNContext ctx; N_Vector y; SUNMatrix A = NULL; SUNLinearSolver LS = NULL;
    SUNNonlinearSolver NLS = NULL; void *cv; realtype t = 0.0; int ok;
    if (SUNContext_Create(NULL, &ctx)) return 1;
    y = N_VNew_Serial(2, ctx); NV_Ith_S(y, 0) = 1.0; NV_Ith_S(y, 1) = 0.0;
    cv = CVodeCreate(lmm, ctx);
    CVodeInit(cv, f, 0.0, y); CVodeSStolerances(cv, 1e-10, 1e-12);
    if (lmm == CV_BDF) {
        A = SUNDenseMatrix(2, 2, ctx); LS = SUNLinSol_Dense(y, A, ctx); CVodeSetLinearSolver(cv, LS, A);
    } else {
        NLS = SUNNonlinSol_FixedPoint(y, 0, ctx); CVodeSetNonlinearSolver(cv, NLS);
    }
    ok = CVode(cv, 3.0, y, &t, CV_NORMAL) == CV_SUCCESS && fabs(NV_Ith_S(y, 0) - cos(3.0)) < 1e-7;
    CVodeFree(&cv); if (LS) SUNLinSolFree(LS); if (A) SUNMatDestroy(A); if (NLS) SUNNonlinSolFree(NLS);
    N_VDestroy(y); SUNContext_Free(&ctx);
    return !ok;
}
int main(void) { int r = run(CV_BDF) | run(CV_ADAMS); puts(r ? "FAIL" : "OK"); return r; }
"""


def opt_cache_dir() -> Path:
    return cache_dir().with_name("sundials-opt")


def _failure_marker() -> Path:
    return opt_cache_dir().with_name("sundials-opt.failed")


def _run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise SundialsNotFound(f"'{' '.join(map(str, cmd))}' failed (exit {r.returncode}): "
                               f"{(r.stderr or r.stdout).strip()[-800:]}")
    return r


def _sha256(path: Path) -> str:
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def fetch_debian_source(workdir: Path) -> Path:
    """Download the orig tarball of Debian's ``sundials`` source package into
    ``workdir`` and return its path.  ``apt-get source --download-only`` (apt
    checks its signature) when a deb-src line is configured; else apt's
    ``apt-helper download-file`` from the pool directory ``apt-get download
    --print-uris libsundials-dev`` names, accepted only with a pinned
    SHA-256."""
    os.chmod(workdir, 0o755)  # apt's sandbox user must be able to write here
    if shutil.which("apt-get") is None:
        raise SundialsNotFound("apt-get is not available to fetch the SUNDIALS source")
    r = subprocess.run(["apt-get", "source", "--download-only", "-qq", "sundials"], cwd=workdir,
                       capture_output=True, text=True)
    tarballs = sorted(workdir.glob("sundials_*.orig.tar.*"))
    if r.returncode == 0 and tarballs:
        return tarballs[0]
    # no deb-src line: the pool directory of the binary package holds the source too
    r = _run(["apt-get", "download", "--print-uris", "libsundials-dev"])
    uri = r.stdout.split()[0].strip("'") if r.stdout.split() else ""
    deb_version = r.stdout.split()[1].split("_")[1] if len(r.stdout.split()) > 1 else ""
    if not uri.startswith(("http://", "https://")) or not deb_version:
        raise SundialsNotFound(f"cannot tell where libsundials-dev comes from: {r.stdout.strip()[:300]!r}")
    upstream = deb_version.split(":")[-1].rsplit("-", 1)[0]
    name = f"sundials_{upstream}.orig.tar.xz"
    if name not in _PINNED_SOURCES:
        raise SundialsNotFound(f"no deb-src line for apt and no pinned checksum for {name} "
                               "(this module knows " + ", ".join(_PINNED_SOURCES) + ")")
    url = uri.rsplit("/", 1)[0] + "/" + name.replace("+", "%2b")
    helper = Path("/usr/lib/apt/apt-helper")
    target = workdir / name
    if helper.is_file():
        _run([str(helper), "download-file", url, str(target), f"SHA256:{_PINNED_SOURCES[name]}"])
    else:
        import urllib.request
        urllib.request.urlretrieve(url, target)  # noqa: S310 (checked below)
    if _sha256(target) != _PINNED_SOURCES[name]:
        raise SundialsNotFound(f"{url} does not have the expected SHA-256")
    return target


def _configure_h(template: str, values: dict, defines: set) -> str:
    """CMake's configure_file for sundials_config.in."""
    import re
    out = []
    for line in template.splitlines():
        m = re.match(r"#cmakedefine01\s+(\w+)", line)
        if m:
            line = f"#define {m.group(1)} {int(m.group(1) in defines)}"
        else:
            m = re.match(r"#cmakedefine\s+(\w+)(.*)", line)
            if m:
                line = f"#define {m.group(1)}{m.group(2)}" if m.group(1) in defines else \
                    f"/* #undef {m.group(1)} */"
        out.append(re.sub(r"@(\w+)@", lambda k: str(values.get(k.group(1), "")), line))
    return "\n".join(out) + "\n"


def build_optimised(dest: Path, tarball: Path | None = None, jobs: int | None = None) -> Path:
    """Compile the objects of SUNDIALS' ``libsundials_cvode.a`` from Debian's
    source (``tarball``, downloaded if None) with ``$CC -O2 -fPIC`` into that
    one static archive under ``dest`` (include/, lib/), after a smoke test."""
    import re
    import tarfile
    from concurrent.futures import ThreadPoolExecutor
    cc = os.environ.get("CC", "gcc")
    ar = os.environ.get("AR", "ar")
    for tool in (cc, ar):
        if shutil.which(tool) is None:
            raise SundialsNotFound(f"'{tool}' not found (needed to build SUNDIALS)")
    with tempfile.TemporaryDirectory(prefix="pdbfs-sundials-build-") as tmp:
        tmp = Path(tmp)
        if tarball is None:
            tarball = fetch_debian_source(tmp)
        wanted = ("include/", "src/sundials/", *sorted({f.rsplit("/", 1)[0] + "/" for f in _CVODE_SOURCES}),
                  "CMakeLists.txt", "LICENSE", "NOTICE")
        with tarfile.open(tarball) as tf:
            members = []
            for mem in tf.getmembers():
                rel = mem.name.split("/", 1)[1] if "/" in mem.name else ""
                if (mem.isfile() or mem.isdir()) and rel.startswith(wanted) and ".." not in mem.name:
                    members.append(mem)
            if not members:
                raise SundialsNotFound(f"{tarball.name} does not look like the SUNDIALS source")
            top = members[0].name.split("/", 1)[0]
            if hasattr(tarfile, "data_filter"):
                tf.extractall(tmp / "src", members=members, filter="data")
            else:
                tf.extractall(tmp / "src", members=members)
        src = tmp / "src" / top
        cmake = (src / "CMakeLists.txt").read_text()
        ver = {k: re.search(rf'set\(PACKAGE_VERSION_{k} "([^"]*)"\)', cmake).group(1)
               for k in ("MAJOR", "MINOR", "PATCH", "LABEL")}
        version = f"{ver['MAJOR']}.{ver['MINOR']}.{ver['PATCH']}" + (f"-{ver['LABEL']}" if ver["LABEL"] else "")
        if ver["MAJOR"] != "6":
            raise SundialsNotFound(f"SUNDIALS source {tarball.name} is version {version}; the wrapper "
                                   "needs the 6.x API")
        stage = Path(tempfile.mkdtemp(prefix=".stage-", dir=_ensure(dest.parent)))
        os.chmod(stage, 0o755)
        try:
            inc = stage / "include"
            for d in _HEADER_DIRS:
                if (src / "include" / d).is_dir():
                    shutil.copytree(src / "include" / d, inc / d)
            for f in _HEADER_FILES:
                if (src / "src" / "sundials" / f).is_file():
                    shutil.copy2(src / "src" / "sundials" / f, inc / f)
            builds = "\n".join(f"#define SUNDIALS_{m} 1" for m in (
                "CVODE", "NVECTOR_SERIAL", "SUNMATRIX_BAND", "SUNMATRIX_DENSE", "SUNMATRIX_SPARSE",
                "SUNLINSOL_BAND", "SUNLINSOL_DENSE", "SUNLINSOL_PCG", "SUNLINSOL_SPBCGS", "SUNLINSOL_SPFGMR",
                "SUNLINSOL_SPGMR", "SUNLINSOL_SPTFQMR", "SUNNONLINSOL_NEWTON", "SUNNONLINSOL_FIXEDPOINT"))
            values = {"SUNDIALS_DEPRECATED_MSG_MACRO": "__attribute__ ((__deprecated__(msg)))",
                      "PACKAGE_VERSION": version, "PACKAGE_VERSION_MAJOR": ver["MAJOR"],
                      "PACKAGE_VERSION_MINOR": ver["MINOR"], "PACKAGE_VERSION_PATCH": ver["PATCH"],
                      "PACKAGE_VERSION_LABEL": ver["LABEL"], "PRECISION_LEVEL": "#define SUNDIALS_DOUBLE_PRECISION 1",
                      "INDEX_TYPE": "#define SUNDIALS_INT64_T 1", "SUNDIALS_CINDEX_TYPE": "int64_t",
                      "SUNDIALS_LOGGING_LEVEL": "0", "SUNDIALS_MAX_SPRINTF_SIZE": "5000",
                      "SUNDIALS_CONFIGH_BUILDS": builds}
            template = (src / "include" / "sundials" / "sundials_config.in").read_text()
            (inc / "sundials" / "sundials_config.h").write_text(_configure_h(template, values, _CONFIG_DEFINES))
            (inc / "sundials" / "sundials_export.h").write_text(_EXPORT_H)
            (inc / "sundials" / "sundials_config.in").unlink(missing_ok=True)
            objdir = tmp / "obj"
            objdir.mkdir()
            flags = OPT_CFLAGS + [f"-I{inc}", f"-I{src / 'src' / 'sundials'}", f"-I{src / 'src' / 'cvode'}"]
            objs = [objdir / (Path(f).stem + ".o") for f in _CVODE_SOURCES]

            def compile_one(i):
                _run([cc, *flags, "-c", str(src / _CVODE_SOURCES[i]), "-o", str(objs[i])])

            with ThreadPoolExecutor(max_workers=jobs or os.cpu_count() or 2) as pool:
                list(pool.map(compile_one, range(len(objs))))
            (stage / "lib").mkdir()
            _run([ar, "rcs", str(stage / "lib" / "libsundials_cvode.a"), *map(str, objs)])
            # smoke test: a static CVODE program (BDF + dense LU, Adams + fixed point)
            (tmp / "smoke.c").write_text(_SMOKE_TEST)
            _run([cc, "-std=gnu99", "-O1", f"-I{inc}", str(tmp / "smoke.c"), "-o", str(tmp / "smoke"),
                  str(stage / "lib" / "libsundials_cvode.a"), "-lm"])
            _run([str(tmp / "smoke")])
            for f in ("LICENSE", "NOTICE"):
                if (src / f).is_file():
                    shutil.copy2(src / f, stage / f)
            (stage / "ORIGIN").write_text(f"{tarball.name}, built by pdbfs.fmu.sundials with {cc} "
                                          f"{' '.join(OPT_CFLAGS)}\n")
            if dest.exists():
                shutil.rmtree(stage)  # another process was faster
            else:
                os.replace(stage, dest)
        finally:
            if stage.exists():
                shutil.rmtree(stage, ignore_errors=True)
    return dest


#: a failed build is retried after this many seconds (or when the marker is deleted)
RETRY_AFTER = 24 * 3600


def _recent_failure(marker: Path) -> bool:
    import time
    try:
        return time.time() - marker.stat().st_mtime < RETRY_AFTER
    except OSError:
        return False


def _optimised(fetch: bool) -> Sundials | None:
    """The optimised build from the cache, building it first if needed and
    allowed; None (with a warning on a failed build) otherwise."""
    dest = opt_cache_dir()
    s = _from_prefix(dest, f"{dest} (-O2 build of Debian's source)")
    if s is not None or not fetch or os.environ.get("PDBFS_SUNDIALS_BUILD", "1") in ("0", "no", "false"):
        return s
    marker = _failure_marker()
    if _recent_failure(marker):
        return None
    import fcntl
    import warnings
    with open(_ensure(dest.parent) / ".sundials-opt.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one build at a time; the others wait and reuse it
        try:
            s = _from_prefix(dest, f"{dest} (-O2 build of Debian's source)")
            if s is None and not _recent_failure(marker):
                build_optimised(dest)
                s = _from_prefix(dest, f"{dest} (-O2 build of Debian's source)")
        except Exception as err:  # any failure: fall back to Debian's archives
            marker.write_text(f"{type(err).__name__}: {err}\n")
            warnings.warn(f"could not build an optimised SUNDIALS ({err}); using Debian's unoptimised "
                          f"archives (delete {marker} to retry)", RuntimeWarning, stacklevel=3)
            return None
    return s


def find_sundials(fetch: bool = True) -> Sundials:
    """The SUNDIALS to link into an FMU: ``$PDBFS_SUNDIALS_DIR``, else the
    optimised build (built once if ``fetch``), else Debian's archives
    (downloaded if none are found and ``fetch`` is true)."""
    env = os.environ.get("PDBFS_SUNDIALS_DIR")
    if env:
        s = _from_prefix(Path(env), f"PDBFS_SUNDIALS_DIR={env}")
        if s is None:
            raise SundialsNotFound(f"PDBFS_SUNDIALS_DIR={env} has no include/cvode/cvode.h and "
                                   "lib/libsundials_cvode.a")
        return s
    s = _optimised(fetch)
    if s is not None:
        return s
    cache = cache_dir()
    s = _from_prefix(cache, str(cache))
    if s is not None:
        return s
    s = _system()
    if s is not None:
        return s
    if not fetch:
        raise SundialsNotFound(f"SUNDIALS static archives not found (looked in $PDBFS_SUNDIALS_DIR, "
                               f"{opt_cache_dir()}, {cache} and the system)")
    try:
        fetch_debian(cache)
    except SundialsNotFound:
        # nothing works here (no apt lists, no network?): try the build again next time
        _failure_marker().unlink(missing_ok=True)
        raise
    s = _from_prefix(cache, f"{cache} (Debian libsundials-dev)")
    if s is None:
        raise SundialsNotFound(f"unpacked SUNDIALS into {cache} but cannot find it there")
    return s
