"""The sources of a source FMU: the part of SUNDIALS that CVODE needs, laid
out so that a plain C compiler builds the binary with ``sources/`` as the
only include directory (what FMI 2.0's ``<SourceFiles>`` and FMPy's
``fmpy compile`` give a build).

    sources/*.c, *.h            the FMI wrapper and the generated model
    sources/cvode/ sundials/    SUNDIALS' public headers that are included,
      nvector/ sunmatrix/ ...   with a portable sundials_config.h and
                                sundials_export.h; sundials/LICENSE (BSD-3)
    sources/sundials_src/       SUNDIALS' C files that CVODE links (below)
                                and the internal headers they include

The C files are what the linker takes from the CMake build's archives for
the CVODE loop (measured with a link map): CVODE, the serial vector, dense
and band matrices and linear solvers, Newton and fixed-point iterations and
the generic layer.
"""
from __future__ import annotations

import re
import shutil
from pathlib import Path

from pdbfs.native.sundials import SundialsSources

#: SUNDIALS' C files the CVODE loop links, relative to the source's src/
SUNDIALS_C = (
    "cvode/cvode.c", "cvode/cvode_io.c", "cvode/cvode_ls.c", "cvode/cvode_nls.c", "cvode/cvode_proj.c",
    "nvector/serial/nvector_serial.c",
    "sunmatrix/dense/sunmatrix_dense.c", "sunmatrix/band/sunmatrix_band.c",
    "sunlinsol/dense/sunlinsol_dense.c", "sunlinsol/band/sunlinsol_band.c",
    "sunnonlinsol/newton/sunnonlinsol_newton.c", "sunnonlinsol/fixedpoint/sunnonlinsol_fixedpoint.c",
    "sundials/sundials_band.c", "sundials/sundials_context.c", "sundials/sundials_dense.c",
    "sundials/sundials_linearsolver.c", "sundials/sundials_logger.c", "sundials/sundials_math.c",
    "sundials/sundials_matrix.c", "sundials/sundials_nonlinearsolver.c", "sundials/sundials_nvector.c",
    "sundials/sundials_nvector_senswrapper.c",
)
#: folder of SUNDIALS' C files inside sources/
SRC_DIR = "sundials_src"
#: SUNDIALS' licence inside sources/
LICENSE = "sundials/LICENSE"

_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)

#: SUNDIALS' export macros without CMake: nothing exported from a DLL, and
#: hidden on ELF so that an FMU's CVODE never meets another SUNDIALS
_EXPORT_H = """\
/* sundials_export.h for pdbfs source FMUs (SUNDIALS' CMake generates its own):
 * SUNDIALS is compiled into the FMU's binary and nothing of it is exported. */
#ifndef SUNDIALS_EXPORT_H
#define SUNDIALS_EXPORT_H
#if defined(__GNUC__) && !defined(_WIN32) && !defined(__CYGWIN__)
#  define SUNDIALS_EXPORT __attribute__((visibility("hidden")))
#else
#  define SUNDIALS_EXPORT
#endif
#define SUNDIALS_NO_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED
#define SUNDIALS_DEPRECATED_EXPORT SUNDIALS_EXPORT
#define SUNDIALS_DEPRECATED_NO_EXPORT SUNDIALS_EXPORT
#endif
"""


def portable_config(generated: str) -> str:
    """sundials_config.h as SUNDIALS' CMake wrote it, made independent of the
    compiler it was written for (deprecation attributes off, no POSIX timers,
    which only SUNDIALS' profiler uses; the profiler is off)."""
    out = []
    for line in generated.splitlines():
        s = line.strip()
        if s.startswith("#") and "define SUNDIALS_DEPRECATED_MSG(msg)" in s:
            line = "#  define SUNDIALS_DEPRECATED_MSG(msg)"
        elif s == "#define SUNDIALS_HAVE_POSIX_TIMERS":
            line = "/* #undef SUNDIALS_HAVE_POSIX_TIMERS */"
        out.append(line)
    text = "\n".join(out) + "\n"
    if "#define SUNDIALS_VERSION " not in text:
        raise ValueError("not a sundials_config.h")
    return text


def add_sundials(dest: Path, own_sources: list[Path], sources: SundialsSources, config_h: Path) -> list[str]:
    """Copy into ``dest`` (an FMU's sources/) the SUNDIALS files that
    ``own_sources`` and SUNDIALS_C include, transitively, with the portable
    config (from ``config_h``, the generated one of the CMake build) and the
    licence. Returns the C files to compile, relative to ``dest``."""
    pool = {}   # internal headers by name
    for d in {Path(c).parent for c in SUNDIALS_C}:
        for h in (sources.src / d).glob("*.h"):
            pool.setdefault(h.name, h)
    (dest / SRC_DIR).mkdir(exist_ok=True)
    todo = list(own_sources)
    c_files = []
    for rel in SUNDIALS_C:
        target = dest / SRC_DIR / Path(rel).name
        shutil.copy2(sources.src / rel, target)
        todo.append(target)
        c_files.append(f"{SRC_DIR}/{target.name}")
    generated = {"sundials/sundials_config.h": portable_config(config_h.read_text()),
                 "sundials/sundials_export.h": _EXPORT_H}
    seen = set()
    while todo:
        f = todo.pop()
        for inc in _INCLUDE.findall(f.read_text(errors="replace")):
            key = (inc, f.parent.name == SRC_DIR)
            if key in seen:
                continue
            seen.add(key)
            target = None
            if inc in generated:
                target = dest / inc
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_text(generated[inc])
            elif (sources.include / inc).is_file():
                target = dest / inc
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(sources.include / inc, target)
            elif "/" not in inc and inc in pool and f.parent.name == SRC_DIR:
                target = dest / SRC_DIR / inc
                shutil.copy2(pool[inc], target)
            if target is not None:
                todo.append(target)
    (dest / LICENSE).parent.mkdir(parents=True, exist_ok=True)
    shutil.copy2(sources.license, dest / LICENSE)
    return c_files


_README = """\
Sources of the FMU '{ident}' exported by pdbfs.fmu (FMI {v}.0)
=====================================================

fmi{v}_functions.c      generic FMI {v}.0 plumbing: life cycle, variables, logging
fmi{v}_interfaces.c     the Model Exchange and Co-Simulation calls
fmi{v}_state.c          FMU state: get, set, serialise
{prefix_h}lifecycle.c           the life cycle: instantiate, initialise, terminate, reset, free
model.c               the model on the generated functions, logging
values.c              variables by value reference
snapshot.c            the FMU state
model_exchange.c      what Model Exchange asks of the model
derivatives.c         directional and adjoint derivatives (CasADi's forward and reverse AD)
cosimulation.c        the co-simulation loop, on pdbfs_cvode.c
pdbfs_cvode.c/h       CVODE through the rig's non-smooth points (restart at every
                      root of the event indicators, dense output)
fmu_instance.h        the instance these files share (no FMI header: any version)
pdbfs_model.h         generated: sizes, value references, parameter table, GUID
pdbfs_model_funcs.c/h generated by CasADi {casadi}: ode, Jacobian, outputs, start
                      values, event indicators, calculated parameters
fmi{v}*.h               FMI {v}.0 standard headers (as FMPy ships them)
pdbfs_names.h         generated: the private name of every function and variable
                      but the FMI functions ([FMI{v}_FUNCTION_PREFIX]<model>_<hash>_<name>);
                      every C file here includes it first (one line added on top)
{sundials_part}
The binaries in this FMU ({platforms}) were linked with SUNDIALS {sundials}
built with SUNDIALS' own CMake (static, -O2).
"""

_README_SUNDIALS = """\
{SRC_DIR}/         SUNDIALS {sundials} C sources that CVODE needs (CVODE, serial
                      vector, dense and band matrices and linear solvers, Newton
                      and fixed point, the generic layer) with their internal headers
cvode/ sundials/ nvector/ sunmatrix/ sunlinsol/ sunnonlinsol/
                      SUNDIALS' public headers; sundials/sundials_config.h and
                      sundials_export.h are portable versions of the generated ones
{LICENSE}      SUNDIALS' licence (BSD-3-Clause)

{listing} lists every C file to compile, so a tool that builds
source FMUs (fmpy compile, OpenModelica, Dymola) needs no help. By hand,
with this folder as the only include directory:

  Linux:    gcc -O2 -fPIC -shared -fvisibility=hidden -I. *.c {SRC_DIR}/*.c \\
                -o {ident}.so -lm
  Windows:  x86_64-w64-mingw32-gcc -O2 -shared -I. *.c {SRC_DIR}/*.c \\
                -o {ident}.dll -static
  macOS:    clang -O2 -shared -fvisibility=hidden -I. *.c {SRC_DIR}/*.c -o {ident}.dylib

and put the library in binaries/<platform>/ of the FMU. (pdbfs's tests build
these sources with `fmpy compile` on Linux (GCC) and with the MinGW line
above; GCC attributes are used only under __GNUC__, so MSVC may take them
too, untested.)

The C math library: on Linux the binary must be linked with -lm
({libm}). `fmpy compile` links none: its binary loads only into a
host that has libm loaded already (Python has; a C program may not:
"undefined symbol: tanh").
With FMPy, add it at the end of the link line:

  python -c "from fmpy.build import build_platform_binary as b; b('<unzipped FMU>',
      cmake_options={{'CMAKE_C_STANDARD_LIBRARIES:STRING': '-lm'}})"
"""

_README_NO_SUNDIALS = """\
SUNDIALS' sources were not available when this FMU was exported: rebuilding
needs a SUNDIALS 6.x CVODE built as position-independent static archives:

  gcc -O2 -fPIC -shared -fvisibility=hidden -I. -I<sundials>/include *.c \\
      -o {ident}.so <sundials>/lib/libsundials_cvode.a -lm -Wl,--exclude-libs,ALL
"""

#: where each FMI version lists the C files of a source build
_LISTING = {2: "modelDescription.xml (<SourceFiles>)", 3: "buildDescription.xml"}


def readme_txt(ident: str, fmi_version: int, casadi: str, sundials: str, platforms: list[str],
               with_sundials: bool) -> str:
    """sources/README.txt: what each file is and how to build the binary by hand."""
    libm = {2: "FMI 2.0's <SourceFiles> cannot say so",
            3: 'buildDescription.xml names it, <Library name="m">, in the configurations of '
               "x86_64-linux and aarch64-linux"}[fmi_version]
    part = (_README_SUNDIALS if with_sundials else _README_NO_SUNDIALS).format(
        libm=libm, ident=ident, sundials=sundials, SRC_DIR=SRC_DIR, LICENSE=LICENSE, listing=_LISTING[fmi_version])
    prefix_h = ("fmi2_prefix.h         fmi2Functions.h with FMI2_FUNCTION_PREFIX honoured (FMPy's copy\n"
                "                      of the header ignores it)\n") if fmi_version == 2 else ""
    return _README.format(prefix_h=prefix_h, ident=ident, v=fmi_version, casadi=casadi, sundials=sundials, sundials_part=part,
                          platforms=", ".join(platforms))
