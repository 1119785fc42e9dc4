"""Building the compiled backend's shared library of a DAE (used by
compiled.py), in two parts compiled by ``zig cc`` (pdbfs.native.toolchain;
``$CC`` if set):

* the drivers, the same for every rig, compiled once per machine, compiler
  command and set of sources into objects in the cache (:func:`drivers`):
  the generic C of pdbfs/native/c/library/ (``pdbfs_batch.c``: one run over
  an output grid; ``pdbfs_summary.c``: many points reduced to their
  summaries, with ``pdbfs_record.c`` and ``pdbfs_pulse.c``), the explicit
  method and the CVODE loop shared with the FMU (native/c/shared/). They
  read a rig's sizes at run time (``pdbfs_rig``, ``pdbfs_batch_model.h``);
* the explicit method's step arithmetic specialised to a state count
  (``pdbfs_erk_sized.c``), compiled once per machine and state count into
  the same folder (:func:`erk_sized`);
* per rig, only its own C: the CasADi-generated model functions and its
  sizes (``pdbfs_batch_model.c``), compiled and linked with those objects
  and the static CVODE of pdbfs.native.sundials into the library (calls
  between the parts are calls between files, as they were when one command
  compiled them all).

Without CVODE at hand the library is built for the explicit method alone
(``pdbfs_cvode_none.c`` in place of the CVODE loop, no SUNDIALS at all):
``sundials_for`` decides; the drivers are compiled for each of the two.

The library is cached on disk as ``$XDG_CACHE_HOME/pdbfs/compiled/<hash>.so``
(``.dll`` on Windows, ``.dylib`` on macOS; default ``~/.cache/pdbfs``), the
hash covering the generated C, the drivers, the compiler commands and the
SUNDIALS archives; the drivers' objects in ``drivers/<hash>/``. Both are
written atomically (the drivers under a file lock), so concurrent processes
may build the same library.
"""
from __future__ import annotations

import hashlib
import os
import re
import shutil
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import casadi as ca

from pdbfs.native import codegen, specialise, straight, toolchain
from pdbfs.native.codegen import (CVODE_DRIVER, ERK_DRIVER, ERK_SIZE_HEADER, FUNCS, LIBRARY_C,
                                  POW_HELPER, STRAIGHT, check_compiler_memory, compile_command,
                                  erk_size_header, generate, model_functions, object_command,
                                  run_compiler, usual_values)
from pdbfs.native.sundials import Sundials, SundialsNotFound, cache_lock, cache_root, find_sundials

from ..results.summary_run import LOOK_AHEAD, MAX_WINDOWS_AHEAD, WINDOW, summary_step

C_DIR = LIBRARY_C
DRIVERS = tuple(C_DIR / n for n in ("pdbfs_batch.c", "pdbfs_summary.c", "pdbfs_record.c",
                                     "pdbfs_record.h", "pdbfs_record_pool.c", "pdbfs_pulse.c",
                                     "pdbfs_pulse.h", "pdbfs_batch_erk.c", "pdbfs_erk_grid.c",
                                     "pdbfs_run_summary.c", "pdbfs_run_trajectory.c",
                                     "pdbfs_segments.c", "pdbfs_batch_model.h")) + ERK_DRIVER
#: the CVODE loop's stand-in in a library without CVODE (the explicit method alone)
NO_CVODE = tuple(f for f in CVODE_DRIVER if f.name not in ("pdbfs_cvode.c", "pdbfs_cvode_ls.c")) + \
    (C_DIR / "pdbfs_cvode_none.c",)
#: the C file of the lists above compiled for each state count (the others: drivers())
SIZED_C = "pdbfs_erk_sized.c"
#: the rig's sizes, generated (pdbfs_batch_model.h declares them)
RIG_SIZES = "pdbfs_batch_model.c"
ABI = 10

#: the summary roles the summary driver knows, in its order (native/c/library/pdbfs_summary.c)
ROLES = ("pressure", "contact_force", "piston_displacement", "striker_velocity")

#: the model functions the drivers call (native/codegen.model_functions)
FUNCTIONS = ("ode", "jac", "events", "events_both", "start", "conditions", "roles", "roles_dot",
             "roles_both", "ode_q", "jac_q", "limits")

#: rig libraries, and sets of drivers, compiled by this process (tests check what is rebuilt)
BUILDS = 0
DRIVER_BUILDS = 0


def cache_dir() -> Path:
    """The folder of the compiled rigs' shared libraries, in pdbfs's cache."""
    return cache_root() / "compiled"


def drivers_dir() -> Path:
    """The folder of the drivers' objects (one folder per machine and sources), in pdbfs's cache."""
    return cache_root() / "drivers"


def sundials_for(cvode: bool | None) -> Sundials | None:
    """The host's CVODE for a library: ``cvode`` True: needed (its sources
    fetched if need be; SundialsNotFound if they cannot be had); None: where
    it is at hand without the network (else None: the explicit method's
    library); False: none."""
    if cvode is False:
        return None
    try:
        return find_sundials(fetch=bool(cvode), target=toolchain.host_target())
    except SundialsNotFound:
        if cvode:
            raise
        return None


#: ``sd`` of build() and fingerprint() when not given: the CVODE at hand, if any
AT_HAND = "at hand"


def _sources(sd) -> tuple[Path, ...]:
    return (*DRIVERS, *(CVODE_DRIVER if sd is not None else NO_CVODE))


def roles_of(dae) -> list[str]:
    """The output names that play the summary driver's roles, in ROLES order."""
    signals = getattr(dae, "signals", {}) or {}
    return [signals[r] for r in ROLES if signals.get(r) in dae.y_names]


def follow_lines(dae) -> list[str]:
    """How the summary driver follows a pulse cut off at t_end (native/c/library/pdbfs_summary.c's
    follow()): summary_run.py's grid and look-ahead, so that both decide alike; C initialisers
    of pdbfs_rig's fields."""
    return [f".summary_step = {summary_step(dae)!r}", f".follow_window = {WINDOW}",
            f".follow_horizons = {float(LOOK_AHEAD)!r}", f".follow_windows = {MAX_WINDOWS_AHEAD}"]


def rig_sizes(dae, work) -> str:
    """pdbfs_batch_model.c: the rig's sizes, work sizes (``work``) and the summary's roles."""
    signals = getattr(dae, "signals", {}) or {}
    present = [r for r in ROLES if signals.get(r) in dae.y_names]
    fields = [f".nx = {dae.x.numel()}", f".np = {dae.p.numel()}", f".ne = {dae.events.numel()}",
              f".nr = {len(present)}",
              *(f".role_{f} = {present.index(r) if r in present else -1}"
                for r, f in zip(ROLES, ("pressure", "force", "disp", "velocity"))),
              f".nl = {len(dae.limits)}",                  # variables' ranges (pdbfs_limits)
              f".nte = {dae.time_events.numel()}",         # the first NTE events: t - t_i
              *follow_lines(dae),
              *(f".sz_{n} = {w}" for n, w in zip(("arg", "res", "iw", "w"), work))]
    return "\n".join([f"/* generated by pdbfs.simulation.compiled for rig '{dae.name}' */",
                      '#include "pdbfs_batch_model.h"', "",
                      "const PdbfsRig pdbfs_rig = {", *(f"    {f}," for f in fields), "};", ""])


def _of_p(dae) -> list:
    """The library's functions of p alone, as expressions (fingerprint)."""
    parts = ([e for e, _ in getattr(dae, "conditions", None) or []],
             [e for e, _ in (getattr(dae, "calculated", None) or {}).values()],
             [e for *_, e in getattr(dae, "reduced_starts", None) or []])
    return [ca.densify(ca.vertcat(*part)) if part else ca.SX(0, 1) for part in parts]


def fingerprint(dae, sd: Sundials | None | str = AT_HAND) -> str:
    """A cheap key of the library of ``dae``, known before any code generation:
    the DAE's expressions (serialised), the parameter values the straight-line
    C is specialised for (specialise.worth_fixing), the functions generated
    and how (codegen.py, straight.py), the drivers' text, the compiler command
    and the SUNDIALS archives. Equal fingerprints give the same
    library; a change anywhere gives another (at worst a rebuild)."""
    signals = getattr(dae, "signals", {}) or {}
    force = signals.get("contact_force")
    roles = roles_of(dae)
    pick = lambda names: [dae.y[dae.y_names.index(n)] for n in names]   # noqa: E731
    outs = [ca.densify(e) for e in (dae.ode, dae.events, dae.x0, ca.vertcat(*pick(roles)),
                                    ca.vertcat(*pick([force] if force in dae.y_names else [])),
                                    dae.limits_expr(),
                                    # of p only, but compiled too: the conditions, the
                                    # calculated parameters, the reduced states' starts
                                    *_of_p(dae))]
    f = ca.Function("fingerprint", [dae.t, dae.x, dae.z, dae.p], outs)
    sd = sundials_for(None) if sd is AT_HAND else sd
    host = toolchain.host_target()
    h = hashlib.sha256()
    for part in (f"abi {ABI}", host, ca.__version__, POW_HELPER, dae.name, f.serialize(),
                 "\0".join(FUNCTIONS), "\0".join(STRAIGHT),
                 *(Path(m.__file__).read_text() for m in (codegen, straight, specialise)),
                 f"nte {dae.time_events.numel()}", "\0".join(roles), *follow_lines(dae),
                 repr(sorted(specialise.worth_fixing(f, 3, usual_values(dae)).items())),
                 *(p.read_text() for p in _sources(sd)),
                 "\0".join(_command([Path("@SRC@/x.c")], Path("@OUT@"), [Path("@SRC@")], sd, host)),
                 _archives_stamp(sd)):
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()[:32]


def build(dae, sd: Sundials | None | str = AT_HAND) -> Path:
    """The library of ``dae`` linked with the CVODE ``sd`` (None: the explicit
    method's, without SUNDIALS): from the disk cache (found by its fingerprint
    without code generation, else by the hash of the generated C), or
    compiled into it."""
    sd = sundials_for(None) if sd is AT_HAND else sd
    fast = cache_dir() / f"fp-{fingerprint(dae, sd)}.so"
    if fast.is_file():
        return fast
    target = _build(dae, sd)
    try:     # the fingerprint's name for the next process: a hard link (else a copy)
        tmp = fast.with_name(f".{fast.name}.{os.getpid()}")
        tmp.unlink(missing_ok=True)
        try:
            os.link(target, tmp)
        except OSError:
            shutil.copyfile(target, tmp)
        os.replace(tmp, fast)
    except OSError:
        pass     # no second name: the next process generates the C again, nothing worse
    return target


def write_rig_sources(dae, folder: Path) -> None:
    """The rig's own C into ``folder``: its model functions (pdbfs_model_funcs.c
    and .h: CasADi's, and the straight-line ones) and its sizes (pdbfs_batch_model.c)."""
    signals = getattr(dae, "signals", {}) or {}
    force = signals.get("contact_force")
    funcs = model_functions(dae, FUNCTIONS, roles=roles_of(dae),
                            quad=[force] if force in dae.y_names else [])
    work = generate(funcs, folder, straight=STRAIGHT, values=usual_values(dae))
    (folder / RIG_SIZES).write_text(rig_sizes(dae, work))


def _build(dae, sd: Sundials | None) -> Path:
    global BUILDS
    objects = [*drivers(sd), erk_sized(sd, dae.x.numel())]
    with tempfile.TemporaryDirectory(prefix="pdbfs-batch-") as tmp:
        src = Path(tmp)
        write_rig_sources(dae, src)
        host = toolchain.host_target()
        files = {f.name: f.read_text() for f in _sources(sd) if f.suffix == ".h"}
        c_files = [RIG_SIZES, f"{FUNCS}.c"]
        # the command with placeholders for the temporary paths: part of the key
        cmd_key = _command([*(Path(f"@SRC@/{n}") for n in c_files),
                            *(Path("@DRIVERS@") / o.name for o in objects)],
                           Path("@OUT@"), [Path("@SRC@")], sd, host)
        h = hashlib.sha256()
        for part in (f"abi {ABI}", host, objects[0].parent.name, *files.values(),
                     *((src / n).read_text() for n in (RIG_SIZES, f"{FUNCS}.c", f"{FUNCS}.h")),
                     "\0".join(cmd_key), _archives_stamp(sd)):
            h.update(part.encode())
            h.update(b"\0")
        key = h.hexdigest()[:32]
        target = cache_dir() / f"{key}{toolchain.library_suffix(host)}"
        if target.is_file():
            return target
        for name, text in files.items():
            (src / name).write_text(text)
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=f".{key}-", suffix=target.suffix, dir=target.parent)
        os.close(fd)    # Windows: an open handle forbids the compiler's write and the rename
        part = Path(name)
        try:
            what = f"the compiled model of rig {dae.name}"
            check_compiler_memory(src / f"{FUNCS}.c", what)
            run_compiler(_command([*(src / n for n in c_files), *objects], part, [src], sd, host),
                         what)
            BUILDS += 1
            os.chmod(part, 0o755)
            os.replace(part, target)   # atomic: a concurrent build writes the same bytes
        finally:
            part.unlink(missing_ok=True)
    return target


def drivers(sd: Sundials | None) -> list[Path]:
    """The drivers' objects for a library with the CVODE ``sd`` (None: the
    explicit method alone), compiled once into the cache (``drivers/<key>/``,
    the key covering their sources, the compile command and the SUNDIALS
    archives): a change of any gives another folder. Built in a temporary
    folder under a file lock and renamed whole, so a process never sees a
    part of one; another process waits for the one building them."""
    global DRIVER_BUILDS
    host = toolchain.host_target()
    folder = _drivers_folder(sd, host)
    sources = [f for f in _sources(sd) if f.suffix == ".c" and f.name != SIZED_C]
    objects = [folder / f"{f.stem}.o" for f in sources]
    if all(o.is_file() for o in objects):
        return objects
    with cache_lock(folder):
        if all(o.is_file() for o in objects):
            return objects
        shutil.rmtree(folder, ignore_errors=True)      # a folder left incomplete by hand
        build = Path(tempfile.mkdtemp(prefix=f".{folder.name}-", dir=folder.parent))
        try:
            _write_sources(build, sd)
            with ThreadPoolExecutor(max_workers=max(1, min(4, os.cpu_count() or 1))) as pool:
                list(pool.map(lambda f: run_compiler(
                    _object_command(build / f.name, build / f"{f.stem}.o", build, sd, host),
                    f"the compiled backend's {f.name}"), sources))
            for f in [*build.iterdir()]:
                if f.suffix != ".o":
                    f.unlink()
            os.replace(build, folder)
        finally:
            shutil.rmtree(build, ignore_errors=True)
        DRIVER_BUILDS += 1
    return objects


def erk_sized(sd: Sundials | None, nx: int) -> Path:
    """The object of pdbfs_erk_sized.c for ``nx`` states (a second to compile,
    more for many states), compiled once per machine and state count into
    the drivers' folder (:func:`drivers`; written whole: concurrent
    processes write the same bytes)."""
    host = toolchain.host_target()
    obj = _drivers_folder(sd, host) / f"{Path(SIZED_C).stem}-{int(nx)}.o"
    if obj.is_file():
        return obj
    drivers(sd)                                        # the folder
    with tempfile.TemporaryDirectory(prefix=f".{obj.stem}-", dir=obj.parent) as tmp:
        build = Path(tmp)
        _write_sources(build, sd)
        (build / ERK_SIZE_HEADER).write_text(erk_size_header(nx))
        run_compiler(_object_command(build / SIZED_C, build / obj.name, build, sd, host),
                     f"the explicit method for {nx} states")
        os.replace(build / obj.name, obj)
    return obj


def _drivers_folder(sd, host) -> Path:
    h = hashlib.sha256()
    for part in (f"abi {ABI}", host, ca.__version__, *(f.read_text() for f in _sources(sd)),
                 "\0".join(_object_command(Path("@SRC@/x.c"), Path("@OUT@"), Path("@SRC@"), sd,
                                           host)),
                 _archives_stamp(sd)):
        h.update(part.encode())
        h.update(b"\0")
    return drivers_dir() / h.hexdigest()[:24]


def _write_sources(folder: Path, sd) -> None:
    """The drivers' C and headers into ``folder``, with their declarations of the model functions."""
    for f in _sources(sd):
        shutil.copyfile(f, folder / f.name)
    _declarations(folder)


def _declarations(folder: Path) -> None:
    """pdbfs_model_funcs.h for the drivers: the model functions they call
    (FUNCTIONS), declared as CasADi declares them for every rig (its work
    sizes, which differ, left out: the drivers read pdbfs_rig's)."""
    x = ca.SX.sym("x")
    cg = ca.CodeGenerator(f"{FUNCS}.c", {"with_header": True, "with_export": False, "verbose": False})
    for name in FUNCTIONS:
        cg.add(ca.Function(f"pdbfs_{name}", [x], [x]))
    cg.generate(str(folder) + os.sep)
    (folder / f"{FUNCS}.c").unlink()
    h = folder / f"{FUNCS}.h"
    h.write_text(re.sub(r"^#define pdbfs_\w+_SZ_\w+ .*\n", "", h.read_text(), flags=re.M))


def _command(sources, out, include_dirs, sd, host) -> list[str]:
    """The compile command of the library: for this machine's CPU (it runs nowhere else)."""
    return compile_command(sources, out, include_dirs,
                           toolchain.host_cpu_flags(toolchain.compiler(host)), sd=sd, target=host,
                           cvode=sd is not None)


def _object_command(source, out, include_dir, sd, host) -> list[str]:
    """The command that compiles one of the drivers, with the library's flags."""
    return object_command(source, out, [include_dir],
                          toolchain.host_cpu_flags(toolchain.compiler(host)), sd=sd, target=host,
                          cvode=sd is not None)


def _archives_stamp(sd) -> str:
    """The SUNDIALS archives linked in (path, size, mtime): a rebuilt SUNDIALS
    gives new libraries."""
    if sd is None:
        return "no CVODE"
    parts = [str(sd.include_dir), sd.version]
    for lib in sd.libraries:
        try:
            st = Path(lib).stat()
            parts.append(f"{lib}:{st.st_size}:{st.st_mtime_ns}")
        except OSError:
            parts.append(str(lib))
    return "\n".join(parts)
