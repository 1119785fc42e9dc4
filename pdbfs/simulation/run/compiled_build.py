"""Building the compiled backend's shared library of a DAE (used by
compiled.py): CasADi-generated C of the model functions, the generic drivers
of pdbfs/native/c/library/, ``pdbfs_batch.c`` (one run over an output grid)
and ``pdbfs_summary.c`` (many points reduced to their summaries, with
``pdbfs_record.c`` and ``pdbfs_pulse.c``), the CVODE loop shared with the
FMU (``native/c/shared/pdbfs_cvode.c``) and the static CVODE of pdbfs.native.sundials,
compiled by ``zig cc`` (pdbfs.native.toolchain; ``$CC`` if set). Without
CVODE at hand the library is built for the explicit method alone
(``pdbfs_cvode_none.c`` in place of the CVODE loop, no SUNDIALS at all):
``sundials_for`` decides.

The library is cached on disk as ``$XDG_CACHE_HOME/pdbfs/compiled/<hash>.so``
(``.dll`` on Windows, ``.dylib`` on macOS)
(default ``~/.cache/pdbfs/compiled``), the hash covering the generated C, the
drivers, the compiler command and the SUNDIALS archives; it is written
atomically, so concurrent processes may build the same library.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import tempfile
from pathlib import Path

import casadi as ca

from pdbfs.native import codegen, specialise, straight, toolchain
from pdbfs.native.codegen import (CVODE_DRIVER, ERK_DRIVER, ERK_SIZE_HEADER, FUNCS, LIBRARY_C,
                                  POW_HELPER, STRAIGHT, check_compiler_memory, compile_command,
                                  erk_size_header, generate, model_functions, run_compiler,
                                  sizes_header_lines, usual_values)
from pdbfs.native.sundials import Sundials, SundialsNotFound, cache_root, find_sundials

from ..results.summary_run import LOOK_AHEAD, MAX_WINDOWS_AHEAD, WINDOW, summary_step

C_DIR = LIBRARY_C
DRIVERS = tuple(C_DIR / n for n in ("pdbfs_batch.c", "pdbfs_summary.c", "pdbfs_record.c",
                                     "pdbfs_record.h", "pdbfs_record_pool.c", "pdbfs_pulse.c",
                                     "pdbfs_pulse.h", "pdbfs_batch_erk.c", "pdbfs_erk_grid.c",
                                     "pdbfs_run_summary.c", "pdbfs_run_trajectory.c",
                                     "pdbfs_segments.c")) + ERK_DRIVER
#: the CVODE loop's stand-in in a library without CVODE (the explicit method alone)
NO_CVODE = tuple(f for f in CVODE_DRIVER if f.name != "pdbfs_cvode.c") + \
    (C_DIR / "pdbfs_cvode_none.c",)
HEADER = "pdbfs_batch_model.h"
ABI = 10

#: the summary roles the summary driver knows, in its order (native/c/library/pdbfs_summary.c)
ROLES = ("pressure", "contact_force", "piston_displacement", "striker_velocity")
ROLE_MACROS = ("PRESSURE", "FORCE", "DISP", "VELOCITY")

#: the model functions the drivers call (native/codegen.model_functions)
FUNCTIONS = ("ode", "jac", "events", "events_both", "start", "conditions", "roles", "roles_dot",
             "roles_both", "ode_q", "jac_q", "limits")

#: compilations done by this process (tests check that nothing is rebuilt)
BUILDS = 0


def cache_dir() -> Path:
    """The folder of the compiled rigs' shared libraries, in pdbfs's cache."""
    return cache_root() / "compiled"


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


def _cvode_files(sd) -> tuple[Path, ...]:
    return CVODE_DRIVER if sd is not None else NO_CVODE


def roles_of(dae) -> list[str]:
    """The output names that play the summary driver's roles, in ROLES order."""
    signals = getattr(dae, "signals", {}) or {}
    return [signals[r] for r in ROLES if signals.get(r) in dae.y_names]


def follow_lines(dae) -> list[str]:
    """How the summary driver follows a pulse cut off at t_end (native/c/library/pdbfs_summary.c's
    follow()): summary_run.py's grid and look-ahead, so that both decide alike."""
    return [f"#define PDBFS_SUMMARY_STEP {summary_step(dae)!r}",
            f"#define PDBFS_FOLLOW_WINDOW {WINDOW}",
            f"#define PDBFS_FOLLOW_HORIZONS {float(LOOK_AHEAD)!r}",
            f"#define PDBFS_FOLLOW_WINDOWS {MAX_WINDOWS_AHEAD}"]


def header(dae, work) -> str:
    """The C header of a rig's library: its sizes, work sizes (``work``) and the summary's roles."""
    signals = getattr(dae, "signals", {}) or {}
    present = [r for r in ROLES if signals.get(r) in dae.y_names]
    macros = [f"#define PDBFS_ROLE_{m} {present.index(r) if r in present else -1}"
              for r, m in zip(ROLES, ROLE_MACROS)]
    return "\n".join([
        f"/* generated by pdbfs.simulation.compiled for rig '{dae.name}' */",
        "#ifndef PDBFS_BATCH_MODEL_H", "#define PDBFS_BATCH_MODEL_H",
        f"#define PDBFS_NX {dae.x.numel()}", f"#define PDBFS_NP {dae.p.numel()}",
        f"#define PDBFS_NE {dae.events.numel()}", f"#define PDBFS_NR {len(present)}", *macros,
        f"#define PDBFS_NL {len(dae.limits)}",            # variables' ranges (pdbfs_limits)
        f"#define PDBFS_NTE {dae.time_events.numel()}",   # the first NTE events: t - t_i
        *follow_lines(dae), *sizes_header_lines(work), "#endif", ""])


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
                 *(p.read_text() for p in (*DRIVERS, *_cvode_files(sd))),
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


def _build(dae, sd: Sundials | None) -> Path:
    global BUILDS
    signals = getattr(dae, "signals", {}) or {}
    force = signals.get("contact_force")
    funcs = model_functions(dae, FUNCTIONS, roles=roles_of(dae),
                            quad=[force] if force in dae.y_names else [])
    with tempfile.TemporaryDirectory(prefix="pdbfs-batch-") as tmp:
        src = Path(tmp)
        work = generate(funcs, src, straight=STRAIGHT, values=usual_values(dae))
        hdr = header(dae, work)
        (src / HEADER).write_text(hdr)
        (src / ERK_SIZE_HEADER).write_text(erk_size_header(dae.x.numel()))   # nx is in hdr (the key)
        host = toolchain.host_target()
        files = {f.name: f.read_text() for f in (*DRIVERS, *_cvode_files(sd))}
        c_files = [n for n in files if n.endswith(".c")] + [f"{FUNCS}.c"]
        # the command with placeholders for the temporary paths: part of the key
        cmd_key = _command([Path(f"@SRC@/{n}") for n in c_files], Path("@OUT@"), [Path("@SRC@")],
                           sd, host)
        h = hashlib.sha256()
        for part in (f"abi {ABI}", host, *files.values(), hdr,
                     (src / f"{FUNCS}.c").read_text(), (src / f"{FUNCS}.h").read_text(),
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
            cmd = _command([src / n for n in c_files], part, [src], sd, host)
            run_compiler(cmd, what)
            BUILDS += 1
            os.chmod(part, 0o755)
            os.replace(part, target)   # atomic: a concurrent build writes the same bytes
        finally:
            part.unlink(missing_ok=True)
    return target


def _command(sources, out, include_dirs, sd, host) -> list[str]:
    """The compile command of the library: for this machine's CPU (it runs nowhere else)."""
    return compile_command(sources, out, include_dirs,
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
