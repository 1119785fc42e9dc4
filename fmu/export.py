"""Export a rig's DAE as an FMI 2.0 or 3.0 FMU (Model Exchange + Co-Simulation).

rig -> C code -> FMU: CasADi generates the model's C (``pdbfs.native.codegen``);
the FMI layer is the generic C in ``native/c/fmu/`` (FMI plumbing, Model Exchange,
Co-Simulation on CVODE through ``native/c/shared/pdbfs_cvode.c`` or on the explicit
Runge-Kutta method of ``native/c/shared/pdbfs_erk.c``); a generated
``pdbfs_model.h`` gives it the sizes, value references and parameter table;
``modelDescription.xml`` comes from ``description.py`` (``description3.py``
for FMI 3.0).  Each platform's binary links a static CVODE (``platforms.py``);
``sources/`` carries SUNDIALS' CVODE sources too (``sources.py``), declared
as ``<SourceFiles>`` (FMI 2.0) or in ``buildDescription.xml`` (FMI 3.0),
and ``documentation/index.html`` describes the rig (``documentation.py``).
"""
from __future__ import annotations

import hashlib
import math
import numbers
import os
import re
import shutil
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
import uuid
import warnings
import zipfile
from pathlib import Path

import casadi as ca

from pdbfs.errors import ExportError
from pdbfs.files import scratch_folder, whole
from pdbfs.modelling import DAE
from pdbfs.native.codegen import (CVODE_DRIVER, ERK_DRIVER, ERK_SIZE_HEADER, FMU_C, FUNCS, STRAIGHT,
                                  check_compiler_memory, erk_size_header, generate, usual_values)
from pdbfs.native.sundials import SundialsNotFound, find_sundials_sources

from . import description3
from .description import model_description
from .documentation import index_html
from .header import model_header
from .platforms import PLATFORMS, build_binary, platform_sundials, resolve_platforms, universal_macho
from .rights import (LICENSE_ENTRY, LICENSE_IN_FMU, PDBFS_LICENSE_IN_FMU, check_rights, license_txt,
                     pdbfs_license_text, rights_attrs)
from .sources import LICENSE, SRC_DIR, add_sundials, readme_txt
from .symbols import make_private
from .variables import RTOL_MAX, RTOL_MIN, FmuModel

C_DIR = FMU_C
#: the FMI versions pdbfs writes
FMI_VERSIONS = (2, 3)
#: the version-neutral C: the model, variables, FMU state, Model Exchange, the co-simulation loop
COMMON_FILES = ("fmu_instance.h", "lifecycle.c", "model.c", "values.c", "snapshot.c", "model_exchange.c",
                "derivatives.c", "cosimulation.c", "stiffness.c")
#: the generic wrapper of each FMI version over them
VERSION_FILES = {2: ("fmi2_functions.c", "fmi2_interfaces.c", "fmi2_state.c", "fmi2_prefix.h"),
                 3: ("fmi3_functions.c", "fmi3_interfaces.c", "fmi3_state.c")}
#: the standard headers of each FMI version
VERSION_HEADERS = {2: ("fmi2Functions.h", "fmi2FunctionTypes.h", "fmi2TypesPlatform.h"),
                   3: ("fmi3Functions.h", "fmi3FunctionTypes.h", "fmi3PlatformTypes.h")}

#: the binaries/ folder of each platform in each FMI version (3.0 names them by platform tuple)
BINARY_DIRS = {2: {n: p.fmi2_dir for n, p in PLATFORMS.items()},
               3: {n: p.name for n, p in PLATFORMS.items()}}


def wrapper_files(fmi_version: int = 2) -> list[Path]:
    """The generic C of a pdbfs FMU of ``fmi_version`` (in the package): the
    version's wrapper, the version-neutral model code, the CVODE driver and
    the explicit Runge-Kutta driver (the compiled backend's own files).
    The generated pdbfs_model.h and pdbfs_model_funcs.c/h come on top."""
    return [C_DIR / f for f in (*VERSION_FILES[fmi_version], *COMMON_FILES)] + list(CVODE_DRIVER) \
        + list(ERK_DRIVER)


#: the generic C of an FMI 2.0 FMU
WRAPPER_FILES = wrapper_files(2)

DEFAULT_RTOL = 1e-8


def _fmi_header_dir(fmi_version: int = 2) -> Path:
    """The FMI standard headers of ``fmi_version`` (from $PDBFS_FMI<v>_HEADERS or fmpy)."""
    env = os.environ.get(f"PDBFS_FMI{fmi_version}_HEADERS")
    cands = [Path(env)] if env else []
    try:
        import fmpy
        cands.append(Path(fmpy.__file__).parent / "c-code")
    except ImportError:
        pass
    for d in cands:
        if all((d / h).is_file() for h in VERSION_HEADERS[fmi_version]):
            return d
    raise ExportError(f"FMI {fmi_version}.0 headers ({VERSION_HEADERS[fmi_version][0]} ...) not found: install "
                      f"fmpy or set PDBFS_FMI{fmi_version}_HEADERS to a directory holding them")


def check_fmi_version(fmi_version: int) -> int:
    """``fmi_version`` as 2 or 3, else an ExportError naming it."""
    if isinstance(fmi_version, bool) or fmi_version not in FMI_VERSIONS:
        raise ExportError(f"FMI version {fmi_version!r}: pdbfs writes FMI 2.0 or 3.0 "
                          "(fmi_version or --fmi-version 2 or 3)")
    return int(fmi_version)


def check_experiment(stop_time: float, step_size: float, tolerance: float) -> tuple[float, float, float]:
    """DefaultExperiment's stop time and step size (s) and its tolerance
    checked before any work: a finite stop time after the start (0 s), a
    step in (0, stop time], a tolerance solver.rtol accepts ([1e-15, 0.1]).

    Parameters
    ----------
    stop_time, step_size : float
        s.
    tolerance : float
        Relative tolerance, 1.

    Returns
    -------
    tuple of float
        (stop_time, step_size, tolerance).

    Raises
    ------
    ExportError
        One line naming the first value that is wrong.
    """
    def number(name: str, v) -> float:
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
            raise ExportError(f"{name} = {v!r}: give a finite number")
        return float(v)
    stop, step, tol = number("stop_time", stop_time), number("step_size", step_size), \
        number("tolerance", tolerance)
    if not stop > 0:
        raise ExportError(f"stop_time = {stop!r} s: the default experiment ends after its start (0 s)")
    if not 0 < step <= stop:
        raise ExportError(f"step_size = {step!r} s: the default communication step is > 0 and at most "
                          f"the stop time ({stop!r} s)")
    if not RTOL_MIN <= tol <= RTOL_MAX:
        raise ExportError(f"tolerance = {tol!r}: a relative tolerance in [{RTOL_MIN:g}, {RTOL_MAX:g}] "
                          "(it is also solver.rtol's default)")
    return stop, step, tol


def _identifier(name: str) -> str:
    ident = re.sub(r"\W", "_", name)
    if not ident or ident[0].isdigit():
        ident = "m_" + ident
    return ident


def export_fmu(dae: DAE, path: str | os.PathLike = "pdbfs.fmu", model_identifier: str | None = None, *,
               stop_time: float = 0.02, step_size: float = 1e-5, tolerance: float = DEFAULT_RTOL,
               keep_build_dir: str | os.PathLike | None = None, cflags: list[str] | None = None,
               fmi_version: int = 2, platforms: list[str] | str | None = None, author: str | None = None,
               license: str | None = None, copyright: str | None = None) -> Path:
    """Write an FMU (FMI 2.0, or 3.0; Model Exchange and Co-Simulation) of a
    compiled rig and return its path (``Rig.export_fmu`` calls it); each rig
    input is an FMU input, held over a co-simulation step (FMI 2.0: on the
    line ``fmi2SetRealInputDerivatives`` gives).

    Parameters
    ----------
    dae : DAE
        The compiled rig (``rig.compile()``); a pure ODE.
    path : str or os.PathLike
        The FMU file to write (``.fmu``); written whole or not at all.
    model_identifier : str, optional
        The C identifier of the binary (default: the DAE's name made one).
    stop_time, step_size : float
        DefaultExperiment's stop time and communication step, s: a finite
        stop time > 0, a step in (0, stop_time].
    tolerance : float
        DefaultExperiment's relative tolerance, also ``solver.rtol``'s
        default, in [1e-15, 0.1].
    keep_build_dir : str or os.PathLike, optional
        A folder to copy the generated C and the build into.
    cflags : list of str, optional
        Extra flags for the C compiler.
    fmi_version : {2, 3}
        FMI 2.0 or 3.0.
    platforms : str or list of str, optional
        The binaries to build: FMI 3.0 platform tuples such as
        ``"x86_64-windows"``, the aliases ``"linux64"``/``"win64"``, or
        ``"all"``, as a list or a comma-separated string; default: the
        host's (``platforms.default_platforms()``).
    author, license, copyright : str, optional
        Written to modelDescription.xml as given (the FMU is its user's
        model); by default no author, and pdbfs's BSD-3-Clause licence and
        copyright. pdbfs's C wrapper's and the embedded SUNDIALS CVODES's
        BSD-3-Clause terms and holders are kept after a value given, their
        texts in ``documentation/licenses/``.

    Returns
    -------
    pathlib.Path
        The FMU written.

    Raises
    ------
    ExportError
        One line, before any work, for a bad argument (PlatformError for an
        unknown platform); also for a DAE with algebraic variables or one
        that differentiates an input, and for a failed build. Nothing is
        left at ``path`` on failure, and no build folder in any case (Ctrl-C
        included).

    Notes
    -----
    Each input of the rig (``dae.inputs``) is an FMU input, held over a
    co-simulation step or on the line FMI 2.0's
    ``fmi2SetRealInputDerivatives`` gives, with the ``min``, ``max`` and
    ``nominal`` of the signals it drives. Co-simulation gives the outputs'
    first and second time derivatives, and (FMI 3.0) intermediate updates
    and early return.
    """
    fmi_version = check_fmi_version(fmi_version)
    stop_time, step_size, tolerance = check_experiment(stop_time, step_size, tolerance)
    check_rights(author=author, license=license, copyright=copyright)
    plats = resolve_platforms(platforms)
    ident = model_identifier or _identifier(dae.name)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", ident):
        raise ExportError(f"model_identifier '{ident}' is not a C identifier")
    _check_target(path)
    path = Path(path)
    model = FmuModel(dae, ident, stop_time, step_size, tolerance)
    what = f"the FMU binary of rig {model.dae.name}"
    with scratch_folder("pdbfs-fmu-") as tmp:
        src = Path(tmp) / "sources"
        src.mkdir()
        # the inner loop's functions as the compiled backend's library has them
        work = generate(model.functions(), src, straight=STRAIGHT, values=usual_values(model.dae))
        hdr_dir = _fmi_header_dir(fmi_version)
        for h in VERSION_HEADERS[fmi_version]:
            shutil.copy2(hdr_dir / h, src / h)
        wrapper = wrapper_files(fmi_version)
        for f in wrapper:
            shutil.copy2(f, src / f.name)
        own_c = [f.name for f in wrapper if f.suffix == ".c"] + [f"{FUNCS}.c"]
        sds = _platform_sundials(plats)
        plats = list(sds)
        sd = next(iter(sds.values()))
        source_files = _add_sundials_sources(src, own_c)
        model.rights = rights_attrs(sd.version, src / LICENSE if source_files else None, bool(source_files),
                                    author=author, license=license, copyright=copyright)
        describe, extra = _describer(model, fmi_version, source_files)
        # GUID: a hash of everything that defines the binary's behaviour
        placeholder = "{00000000-0000-0000-0000-000000000000}"
        h = hashlib.sha256()
        for part in (describe(placeholder), model_header(model, placeholder, work, extra),
                     (src / f"{FUNCS}.c").read_text(), *(f.read_text() for f in wrapper), ident):
            h.update(part.encode())
        guid = "{" + str(uuid.UUID(bytes=h.digest()[:16], version=5)) + "}"
        make_private(src, f"{ident}_{h.hexdigest()[:8]}_", fmi_version, SRC_DIR if source_files else None)
        (src / "pdbfs_model.h").write_text(model_header(model, guid, work, extra))
        (src / ERK_SIZE_HEADER).write_text(erk_size_header(model.nx))
        xml = describe(guid)
        if fmi_version == 3:
            (src / "buildDescription.xml").write_text(description3.build_description(
                model, source_files or own_c, None if source_files else sd.version))
        (src / "README.txt").write_text(readme_txt(ident, fmi_version, ca.__version__, sd.version, plats,
                                                   bool(source_files)))
        check_compiler_memory(src / f"{FUNCS}.c", what)
        binaries, slices = {}, {}

        failed = threading.Event()     # a build failed or was interrupted: start no other

        def build(name: str) -> Path | None:
            if failed.is_set():
                return None
            out = Path(tmp) / "build" / name / f"{ident}{PLATFORMS[name].suffix}"
            out.parent.mkdir(parents=True, exist_ok=True)
            try:
                # the binary links the platform's CVODE archive: CVODE's names as built there
                return build_binary(name, [src / c for c in own_c], [src], out, what,
                                    [*(cflags or []), "-DPDBFS_PREBUILT_CVODE"], sds[name])
            except BaseException:
                failed.set()
                raise
        done = 0
        pool = ThreadPoolExecutor(max_workers=min(len(plats), os.cpu_count() or 1))
        try:
            for name, built in zip(plats, pool.map(build, plats)):
                done += 1
                if len(plats) > 1:       # minutes the first time: each platform said as it ends
                    print(f"pdbfs: [{done}/{len(plats)}] built the FMU's binary for {name}",
                          file=sys.stderr, flush=True)
                arc = f"binaries/{BINARY_DIRS[fmi_version][name]}/{ident}{PLATFORMS[name].suffix}"
                slices.setdefault(arc, []).append(built)
        finally:       # a failure or Ctrl-C: no platform's build starts after it
            pool.shutdown(wait=True, cancel_futures=True)
        for arc, built in slices.items():   # FMI 2.0's darwin64: one universal binary of both Macs
            out = Path(tmp) / arc
            out.parent.mkdir(parents=True, exist_ok=True)
            binaries[arc] = universal_macho(built, out) if len(built) > 1 else Path(shutil.copy2(built[0], out))
        docs = {"documentation/index.html": index_html(model, plats, sd.version, ca.__version__,
                                                       bool(source_files), fmi_version, license),
                LICENSE_ENTRY: license_txt(ident, model.dae.name, fmi_version, sd.version,
                                           src / LICENSE if source_files else None, bool(source_files),
                                           license=license, copyright=copyright),
                PDBFS_LICENSE_IN_FMU: pdbfs_license_text()}
        if source_files:
            docs[LICENSE_IN_FMU] = (src / LICENSE).read_text()
        if keep_build_dir is not None:
            kb = Path(keep_build_dir)
            if kb.exists():
                shutil.rmtree(kb)
            shutil.copytree(tmp, kb)
        _write_zip(path, xml, binaries, src, docs)
    return path


def _describer(model: FmuModel, fmi_version: int, source_files: list[str]):
    """(token -> modelDescription.xml, extra lines of pdbfs_model.h) of
    ``fmi_version``; FMI 2.0 lists ``source_files`` in modelDescription.xml
    (3.0 in buildDescription.xml)."""
    if fmi_version == 3:
        return (lambda token: description3.model_description3(model, token)), \
            tuple(description3.header_lines(model))
    return (lambda guid: model_description(model, guid, source_files)), ()


def check_fmu_name(path: str | os.PathLike) -> None:
    """Refuse an FMU file name that is empty, a folder, or does not end in
    ``.fmu`` (the FMI standard names an FMU so, and tools look for it by
    that extension): an ExportError in one line."""
    if not str(os.fspath(path)).strip():
        raise ExportError("the FMU's file name is empty: name the file to write, e.g. rig.fmu")
    path = Path(path)
    if path.is_dir():
        raise ExportError(f"{path} is a folder: give the FMU's file name (e.g. {path / 'pdbfs.fmu'})")
    if path.suffix.lower() != ".fmu":
        raise ExportError(f"{path}: an FMU's file name ends in .fmu (the FMI standard's "
                          f"extension); name it e.g. {path.with_suffix('.fmu').name}")


def _check_target(path: str | os.PathLike) -> None:
    """Refuse, before any work, an FMU path that cannot be written."""
    check_fmu_name(path)
    path = Path(path)
    probe = path.with_name(path.name + ".part")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(probe, "wb"):
            pass
        probe.unlink()
    except OSError as err:
        raise ExportError(f"cannot write the FMU {path}: {err.strerror or err}") from None


def _platform_sundials(plats: list[str]) -> dict:
    """Each platform's CVODE (compiled once per machine and target)."""
    return {name: platform_sundials(name) for name in plats}


def _add_sundials_sources(src: Path, own_c: list[str]) -> list[str]:
    """SUNDIALS' sources into ``src``; the C files of a source build (``[]``,
    with a warning, when SUNDIALS' sources cannot be had)."""
    try:
        sources = find_sundials_sources()
    except SundialsNotFound as err:
        warnings.warn(f"the FMU ships no SUNDIALS sources ({err}): it cannot be compiled from its "
                      "sources without a SUNDIALS installation", RuntimeWarning, stacklevel=3)
        return []
    own = [src / c for c in own_c] + [src / "pdbfs_cvode.h", src / "fmu_instance.h"]
    return own_c + add_sundials(src, own, sources)


#: the date of every file in the FMU (the zip format's earliest): the same
#: rig exported twice gives the same bytes, whatever the clock says
ZIP_DATE = (1980, 1, 1, 0, 0, 0)


def _write_zip(path: Path, xml: str, binaries: dict[str, Path], src: Path, docs: dict[str, str]) -> None:
    """The FMU at ``path``, written whole or not at all; every entry with
    the same date and permissions, so that its bytes depend on its contents
    only."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with whole(path) as part, zipfile.ZipFile(part, "w", zipfile.ZIP_DEFLATED) as z:
        def put(arc: str, data: str | bytes, mode: int = 0o644) -> None:
            info = zipfile.ZipInfo(arc, ZIP_DATE)
            info.compress_type, info.external_attr = zipfile.ZIP_DEFLATED, mode << 16
            info.create_system = 3    # Unix (the permissions' system) on any host
            z.writestr(info, data)
        put("modelDescription.xml", xml)
        for arc, f in binaries.items():
            put(arc, f.read_bytes(), 0o755)
        for f in sorted(src.rglob("*")):
            if f.is_file():
                put(f"sources/{f.relative_to(src).as_posix()}", f.read_bytes())
        for arc, text in docs.items():
            put(arc, text)
