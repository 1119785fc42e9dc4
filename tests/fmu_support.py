"""Support for the FMU tests (tests/test_fmu_*.py): the real rigs, each
exported once per test process, the CasADi reference, and a log recorder
for fmpy's low-level API.  Not part of the package."""
from __future__ import annotations

import atexit
import shutil
import tempfile
import zlib
from pathlib import Path

import numpy as np

from pdbfs.fmu import export_fmu
from pdbfs.models import hydraulic_pulse_rig, paper_hydraulic_rig, paper_rig, split_piston_rig

#: rigs the FMU tests export: name -> builder
RIG_BUILDERS = {
    "paper": paper_rig,
    # Lankarani-Nikravesh damping: contact.D is a calculated parameter
    "law": lambda: paper_rig(law="lankarani-nikravesh"),
    # the piston split into three masses: ten states
    "split3": lambda: split_piston_rig(3),
    # an oil column with a cavitation clamp: other states, other event indicators
    "hydraulic": paper_hydraulic_rig,
    # a valve pulse: tunable valve times tied by a condition (t_close >= t_open)
    "pulse": hydraulic_pulse_rig,
}

_CACHE: dict = {}


def built_model(kind: str = "paper"):
    """(dae, rig) of one of RIG_BUILDERS, built once per process."""
    if kind not in _CACHE:
        rig = RIG_BUILDERS[kind]()
        _CACHE[kind] = {"model": (rig.compile(), rig)}
    return _CACHE[kind]["model"]


def built_fmu(kind: str = "paper", fmi_version: int = 2) -> str:
    """Export the rig once per process (and FMI version) and return the FMU's path."""
    dae, _ = built_model(kind)
    entry = _CACHE[kind]
    key = "path" if fmi_version == 2 else f"path{fmi_version}"
    if key not in entry:
        d = tempfile.mkdtemp(prefix=f"pdbfs-test-{kind}-")
        atexit.register(shutil.rmtree, d, True)
        entry[key] = str(export_fmu(dae, f"{d}/{kind}.fmu", fmi_version=fmi_version))
    return entry[key]


def built_fmu3(kind: str = "paper") -> str:
    """The FMI 3.0 FMU of the rig, exported once per process."""
    return built_fmu(kind, fmi_version=3)


#: what CMake looks for as a C compiler on PATH
SYSTEM_CCS = ("cc", "gcc", "clang")


def system_cc() -> str | None:
    """The system's C compiler, as CMake would find it ($CC, else cc, gcc or
    clang on PATH), or None on a machine with none (pip alone)."""
    import os
    cc = os.environ.get("CC", "").split()
    return shutil.which(cc[0]) if cc else next(filter(None, map(shutil.which, SYSTEM_CCS)), None)


def cmake_cc(folder, language: str = "cc") -> str | None:
    """The compiler a CMake source build is to be given for ``language``
    ("cc" or "c++", which FMPy's CMake project also asks for): None where the
    system has a C compiler (CMake finds it), else a wrapper script in
    ``folder`` that runs pdbfs's own ``zig cc`` (``zig c++``) for this machine,
    with zig's cache where pdbfs keeps it: a machine with pip alone builds
    the sources too."""
    if system_cc():
        return None
    import shlex

    from pdbfs.native import toolchain
    env = toolchain.zig_env()
    cmd = toolchain.compiler()
    cmd[1] = language                         # zig cc -target ... / zig c++ -target ...
    wrapper = Path(folder) / f"zig-{language}"
    wrapper.parent.mkdir(parents=True, exist_ok=True)
    wrapper.write_text("#!/bin/sh\n" + "".join(
        f"export {k}={shlex.quote(env[k])}\n" for k in ("ZIG_GLOBAL_CACHE_DIR", "ZIG_LOCAL_CACHE_DIR"))
        + f'exec {shlex.join(cmd)} "$@"\n')
    wrapper.chmod(0o755)
    return str(wrapper)


def cmake_env(folder) -> dict:
    """This environment, with ``CC`` and ``CXX`` set to :func:`cmake_cc`'s
    wrappers where the system has no C compiler (CMake reads them on its
    first configure)."""
    import os
    cc = cmake_cc(folder)
    return {**os.environ, **({"CC": cc, "CXX": cmake_cc(folder, "c++")} if cc else {})}


def source_build(fmu: str, dest, cflags=()) -> Path:
    """Unzip ``fmu`` into ``dest`` without its binaries and build the binary
    from sources/ as `fmpy compile` does (FMPy's CMake project, the source
    files the FMU declares), with the system's C compiler, else zig cc
    (:func:`cmake_cc`); returns ``dest``."""
    import zipfile
    from pathlib import Path

    from fmpy.build import build_platform_binary
    dest = Path(dest)
    with zipfile.ZipFile(fmu) as z:
        z.extractall(dest)
    shutil.rmtree(dest / "binaries", ignore_errors=True)
    opts = {"CMAKE_C_FLAGS:STRING": " ".join(cflags)} if cflags else {}
    cc = cmake_cc(dest.parent / f"{dest.name}-cc")
    if cc:
        opts["CMAKE_C_COMPILER:FILEPATH"] = cc
        opts["CMAKE_CXX_COMPILER:FILEPATH"] = cmake_cc(dest.parent / f"{dest.name}-cc", "c++")
    build_platform_binary(str(dest.resolve()), build_dir=None, cmake_options=opts or None)
    return dest


def resealed(ser) -> bytes:
    """A serialised FMU state whose bytes were changed on purpose, with its
    checksum made right again (snapshot.c: the Snapshot's bytes, then their
    CRC-32, least significant byte first), so that what its contents say is
    checked: a state spoilt by someone who knows the format."""
    body = bytes(ser[:-4])
    return body + zlib.crc32(body).to_bytes(4, "little")


def corrupted_states(ser: bytes) -> list[tuple[bytes, str]]:
    """Serialised FMU states of the paper rig spoilt one way each, with the
    word the refusal must name: a negative hammer.m, the error mode, a NaN
    time (each resealed: the checksum alone would refuse them). The
    Snapshot's layout (fmu_instance.h): magic, size (unsigned), token[64],
    mode, type (int), time, p[]."""
    off_mode, off_time = 4 + 4 + 64, 4 + 4 + 64 + 4 + 4
    k = built_model("paper")[0].p_names.index("hammer.m")
    out = []
    for off, value, match in ((off_time + 8 * (1 + k), np.float64(-1.0), "hammer.m"),
                              (off_mode, np.int32(1 << 6), "mode"), (off_time, np.float64(np.nan), "times")):
        bad = bytearray(ser)
        raw = value.tobytes()
        bad[off:off + len(raw)] = raw
        out.append((resealed(bad), match))
    return out


def untyped(dll, name: str):
    """The C function ``name`` of ``dll`` returning an int, its arguments
    passed as given (fmpy declares argument types on its own handle)."""
    import ctypes
    return ctypes.CFUNCTYPE(ctypes.c_int)(ctypes.cast(getattr(dll, name), ctypes.c_void_p).value)


def reference_pressure(rig, params: dict | None = None, t_end: float = 0.02, n_out: int = 2001,
                       rtol: float = 1e-8, atol: float = 1e-10):
    """(t, oil pressure) of the CasADi path (``rig.simulate``)."""
    res = rig.simulate(t_end, n_out=n_out, params=dict(params or {}), rtol=rtol, atol=atol)
    return np.asarray(res.t), np.asarray(res["oil.pressure"])


_LOG: dict = {}


def _shared_callbacks():
    """One set of fmpy callbacks for the process (fmpy's logger proxy is
    global); messages are kept per instance name."""
    if "callbacks" not in _LOG:
        from ctypes import byref

        from fmpy import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
        from fmpy.logging import addLoggerProxy
        messages = _LOG.setdefault("messages", [])

        def log(env, name, status, category, message):
            messages.append((name.decode(errors="replace"), status, category.decode(errors="replace"),
                             message.decode(errors="replace")))

        cb = fmi2CallbackFunctions()
        cb.logger = fmi2CallbackLoggerTYPE(log)
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(cb))
        _LOG["callbacks"] = cb
    return _LOG["callbacks"]


class Recorder:
    """The log messages of the FMU instance called ``name``."""

    def __init__(self, name: str):
        self.name = name
        self.callbacks = _shared_callbacks()

    @property
    def messages(self) -> list[tuple[int, str, str]]:
        return [(s, c, m) for n, s, c, m in _LOG["messages"] if n == self.name]

    def errors(self) -> list[str]:
        return [m for s, _, m in self.messages if s >= 3]

    def clear(self):
        _LOG["messages"][:] = [e for e in _LOG["messages"] if e[0] != self.name]


def fmu_log_text(printed: str) -> str:
    """What FMUs logged in this process: FMPy's printed lines, and the lines
    that reached the shared callbacks instead (once a test used a Recorder,
    FMPy's global logger proxy forwards every FMU's log there)."""
    return printed + "\n".join(m for *_, m in _LOG.get("messages", []))
