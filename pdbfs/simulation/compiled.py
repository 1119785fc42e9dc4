"""The compiled simulation backend (``pdbfs.simulate(..., backend="c")`` and
fast sweeps).

The DAE's model functions are generated as C by CasADi, compiled with
generic drivers and CVODE into one shared library (``compiled_build.py``),
and called through ctypes: ``run`` integrates one point over a whole output
grid (``c/pdbfs_batch.c``); ``summaries`` integrates many points and reduces
each to its summary during the integration (``c/pdbfs_summary.c``, on the
record of ``c/pdbfs_record.c``, the pulse paired in ``c/pdbfs_pulse.c``),
without a Python object per point. Both report CVODE's statistics
(``STAT_KEYS``). The library is built once per rig structure and
loaded once per DAE: parameters, start values, tolerances and the grid are
call arguments, so nothing is rebuilt when they change. ctypes releases the
GIL during a call, so threads run calls in parallel.
"""
from __future__ import annotations

import ctypes
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from pdbfs.errors import ExportError, ParameterError, PdbfsError
from pdbfs.native.sundials import SundialsNotFound

from . import compiled_build as build_lib
from .block import Block
from .compiled_build import ABI, ROLES
from .kept import KeptRun

METHOD_CODES = {"adams": 0, "bdf": 1, "erk": 2}
MSG_LEN = 1024
POINT_MSG_LEN = 320

#: what the summary driver computes, in its order; a key is reported when its role exists.
#: ``complete`` is 1.0 when the pulse ended inside the run (the pressure rose above and fell
#: back below 1 % of its peak, and the contact force is zero at the end), else 0.0
SUMMARY_KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
                "max_piston_displacement", "restitution_coefficient", "complete")
KEY_ROLES = {"peak_pressure": "pressure", "time_of_peak": "pressure", "pulse_duration": "pressure",
             "peak_contact_force": "contact_force", "max_piston_displacement": "piston_displacement",
             "restitution_coefficient": "contact_force", "complete": "pressure"}

#: the solver statistics of one run (RunStatus.stats, summaries(with_stats=True))
STAT_KEYS = ("steps", "rhs_evals", "jac_evals", "root_events", "method", "wall_time")

# return codes of pdbfs_batch_run (c/pdbfs_batch.c); CVODE failures are its negative flags
RC_OK, RC_BAD_INPUT, RC_SETUP, RC_TOO_MUCH_WORK, RC_NOT_FINITE = 0, 1, 2, 3, 4
#: a summary point whose pressure crossings do not alternate (c/pdbfs_summary.c)
RC_BAD_CROSSINGS = 6
#: summaries(): a pulse cut off at t_end the driver could not follow past it (summary.py's)
RC_FOLLOW = 7
INFO_N = 7          # pdbfs_batch_run's info[] (c/pdbfs_batch.c INFO_*)
NSTAT = 6           # pdbfs_summary_batch's stats columns (c/pdbfs_summary.c ST_*)


def solver_name(code: int) -> str:
    """The solver a driver used, from its code (method | nls << 4 | linsol << 8,
    pdbfs_cvode.h): "adams/fixed-point", "adams/newton-dense", "bdf/newton-band", ..."""
    code = int(code)
    if code == 2:
        return "erk/dop853"
    method = "bdf" if code & 15 == 1 else "adams"
    if (code >> 4) & 15 != 2:
        return f"{method}/fixed-point"
    return f"{method}/newton-{'band' if (code >> 8) & 15 == 2 else 'dense'}"


def _text(raw, strip=True) -> str:
    """A C string written into a numpy byte buffer (NUL-terminated), as str."""
    if not raw[0]:
        return ""
    text = raw.tobytes().split(b"\0", 1)[0].decode(errors="replace")
    return text.strip() if strip else text


def _stats(steps, rhs, jac, roots, method, wall) -> dict:
    return {"steps": int(steps), "rhs_evals": int(rhs), "jac_evals": int(jac),
            "root_events": int(roots), "method": solver_name(method), "wall_time": float(wall)}


@dataclass
class RunStatus:
    """What one call of the driver reports."""

    code: int            # 0 ok, RC_* > 0, or CVODE's negative flag
    t_reached: float     # last successful step (t_end on success)
    steps: int           # internal CVODE steps
    roots: int           # event-indicator roots (restarts on rigs under 40 states)
    rhs_evals: int
    cvode_flag: int
    message: str         # CVODE's (or the driver's) message on failure
    #: solver statistics, keys STAT_KEYS: steps, rhs_evals, jac_evals, root_events
    #: (roots of the event indicators), method (the solver used), wall_time (s, the call)
    stats: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.code == RC_OK


class CompiledODE:
    """The shared library of one ODE rig; ``run`` integrates over a grid."""

    def __init__(self, dae):
        if not dae.is_ode:
            raise ParameterError(
                f"backend='c' integrates ODE rigs only; rig {dae.name} keeps {dae.z.numel()} "
                f"algebraic variable(s) ({', '.join(dae.z_names)}): use backend='casadi' (IDAS)")
        if dae.x.numel() == 0:
            raise ParameterError(f"backend='c': rig {dae.name} has no states, nothing to integrate")
        if dae.events.numel() != len(dae.event_names):
            raise PdbfsError(f"rig {dae.name}: {dae.events.numel()} event indicators but "
                             f"{len(dae.event_names)} names")
        self.name = dae.name
        self.nx, self.np, self.ne = dae.x.numel(), dae.p.numel(), dae.events.numel()
        self.nc = len(getattr(dae, "conditions", None) or [])
        self._blocks = threading.local()     # run_summary's buffers, one per thread
        signals = getattr(dae, "signals", {}) or {}
        self.roles = [r for r in ROLES if signals.get(r) in dae.y_names]
        #: 1 where the rig has a contact force: ``run`` then also integrates its impulse
        self.nq = 1 if "contact_force" in self.roles else 0
        #: the summary keys the summary driver gives for this rig
        self.summary_keys = [k for k in SUMMARY_KEYS if KEY_ROLES[k] in self.roles]
        try:
            self.path = self._build(dae)
            try:
                self._lib = self._load(self.path)
            except OSError:   # a damaged cache entry: build it again, once
                self.path.unlink(missing_ok=True)
                self.path = self._build(dae)
                self._lib = self._load(self.path)
        except ExportError as err:   # no compiler, a compiler error, ...
            raise ExportError(f"backend='c' could not build the compiled model of rig "
                              f"{dae.name}: {err}") from err
        except PdbfsError:
            raise
        except SundialsNotFound as err:
            raise PdbfsError(f"backend='c' needs SUNDIALS' CVODE: {err}") from err
        except (RuntimeError, OSError) as err:
            raise PdbfsError(f"backend='c' could not build the compiled model of rig {dae.name}: "
                             f"{err}") from err

    def _build(self, dae) -> Path:
        return build_lib.build(dae)

    def _load(self, path: Path):
        lib = ctypes.CDLL(str(path))
        lib.pdbfs_batch_abi.restype = ctypes.c_int
        lib.pdbfs_batch_abi.argtypes = []
        if lib.pdbfs_batch_abi() != ABI:
            raise PdbfsError(f"{path}: driver ABI {lib.pdbfs_batch_abi()}, expected {ABI}; delete it")
        sizes = (ctypes.c_longlong * 3)()
        lib.pdbfs_batch_sizes.restype = None
        lib.pdbfs_batch_sizes.argtypes = [ctypes.c_void_p]
        lib.pdbfs_batch_sizes(sizes)
        if tuple(sizes) != (self.nx, self.np, self.ne):
            raise PdbfsError(f"{path}: built for {tuple(sizes)} (states, parameters, events), "
                             f"rig {self.name} has {(self.nx, self.np, self.ne)}; delete it")
        f = lib.pdbfs_batch_run
        f.restype = ctypes.c_int
        vp, ll, d = ctypes.c_void_p, ctypes.c_longlong, ctypes.c_double
        f.argtypes = [ll, ll, vp, vp, ll, vp, vp, d, d, ctypes.c_int, d, ll, vp, ctypes.c_char_p, ll]
        self._run = f
        g = lib.pdbfs_summary_batch
        g.restype = ll
        g.argtypes = [ll, ll, vp, d, d, d, ctypes.c_int, d, ll, vp, vp, ctypes.c_char_p, ll, vp]
        self._summaries = g
        h = lib.pdbfs_pulse_pairs
        h.restype = ctypes.c_int
        h.argtypes = [ctypes.c_long, vp, vp, ctypes.c_int, ctypes.c_int, d, d, vp, ctypes.c_char_p,
                      ctypes.c_long]
        self._pulse_pairs = h
        r = lib.pdbfs_run_summary
        r.restype = ctypes.c_int
        # the messages are addresses in a numpy buffer (run_summary): c_void_p
        r.argtypes = [vp, vp, ll, vp, vp, d, d, ctypes.c_int, d, ll, vp, vp, ll, vp, vp, vp, ll, vp]
        self._run_summary = r
        tr = lib.pdbfs_run_trajectory
        tr.restype = ctypes.c_int
        tr.argtypes = [vp, ll, vp, vp, ctypes.c_char_p, ll]
        self._trajectory = tr
        mo = lib.pdbfs_batch_modes
        mo.restype = ctypes.c_int
        mo.argtypes = [vp, vp, d, vp]
        self._modes = mo
        st = lib.pdbfs_batch_start
        st.restype = ctypes.c_int
        st.argtypes = [vp, vp, vp]
        self._start = st
        rel = lib.pdbfs_run_release
        rel.restype = None
        rel.argtypes = [vp]
        self._release = rel
        return lib

    def modes(self, x0, p, t0=0.0):
        """(the largest modulus of an eigenvalue of d(ode)/dx at (t0, x0), the
        fastest decay of a mode that does not oscillate, the largest modulus
        of a mode that does), as stiffness.rates gives them of
        stiffness.fast_modes' eigenvalues; (0, 0, 0) where the Jacobian is
        not finite; None where the eigenvalues did not converge (the caller
        asks LAPACK). x0 and p: float arrays of the rig's sizes."""
        if len(x0) != self.nx or len(p) != self.np:
            raise ParameterError(f"rig {self.name}: {len(x0)} start values and {len(p)} parameters "
                                 f"given, expected {self.nx} and {self.np}")
        b = self._block()           # the arguments where C reads them (an address costs 2 us)
        b.p[:] = p
        b.x0[:] = x0
        code = self._modes(b.addr[0], b.addr[1], float(t0), b.c_addr)
        if code == RC_SETUP:
            raise MemoryError(f"rig {self.name}: no memory for the Jacobian's modes")
        return None if code < 0 else tuple(b.c[:3].tolist())

    def start(self, p) -> np.ndarray:
        """The start values of the parameters ``p`` (pdbfs_batch_start)."""
        b = self._block(p)
        if self._start(b.addr[0], b.addr[1], None):
            raise MemoryError(f"rig {self.name}: no memory for the start values")
        return b.x0.copy()

    def conditions(self, p) -> np.ndarray:
        """The components' conditions at ``p``, each >= 0 where consistent."""
        b = self._block(p)
        if self.nc and self._start(b.addr[0], None, b.c_addr):
            raise MemoryError(f"rig {self.name}: no memory for the conditions")
        return b.c[:self.nc].copy()

    def _block(self, p=None) -> Block:
        """This thread's Block (made on its first call), holding ``p`` if given."""
        b = self._blocks.__dict__.get("block")
        if b is None:
            b = self._blocks.block = Block(self.np, self.nx, self.nc, INFO_N, len(SUMMARY_KEYS),
                                           MSG_LEN, 2 * POINT_MSG_LEN)
        if p is not None:
            if len(p) != self.np:
                raise ParameterError(f"rig {self.name}: {len(p)} parameters given, "
                                     f"expected {self.np}")
            b.p[:] = p
        return b

    # -- run ------------------------------------------------------------------------
    def run(self, t, x0, p, rtol, atol, method="adams", max_step=None, max_num_steps=500000):
        """States on the grid ``t`` (shape (nx, len(t))) and a RunStatus.
        With ``nx + nq`` start values (a rig with a contact force), the last
        is the force's impulse (N s), integrated with the states and given
        as the last row. The arguments are checked again in C: bad ones give
        code RC_BAD_INPUT."""
        t = np.ascontiguousarray(t, dtype=float).ravel()
        x0 = np.ascontiguousarray(x0, dtype=float).ravel()
        p = np.ascontiguousarray(p, dtype=float).ravel()
        if x0.size not in (self.nx, self.nx + self.nq) or p.size != self.np:
            raise ParameterError(f"rig {self.name}: {x0.size} start values and {p.size} parameters "
                                 f"given, expected {self.nx} and {self.np}")
        if method not in METHOD_CODES:
            raise ParameterError(f"unknown method {method!r}; choose one of {', '.join(METHOD_CODES)}")
        nt = t.size
        X = np.empty((x0.size, nt))
        info = np.zeros(INFO_N)
        msg = ctypes.create_string_buffer(MSG_LEN)
        wall = time.perf_counter()
        code = self._run(x0.size, self.np, p.ctypes.data, x0.ctypes.data, nt, t.ctypes.data,
                         X.ctypes.data, float(rtol), float(atol), METHOD_CODES[method],
                         float(max_step or 0.0), int(max_num_steps), info.ctypes.data, msg, MSG_LEN)
        wall = time.perf_counter() - wall
        status = RunStatus(int(code), float(info[0]), int(info[1]), int(info[2]), int(info[3]),
                           int(info[4]), msg.value.decode(errors="replace").strip(),
                           _stats(info[1], info[3], info[5], info[2], info[6], wall))
        return X, status


    def run_summary(self, t, x0, p, rtol, atol, method="erk", max_step=None,
                    max_num_steps=500000, checked=False, keep=False, t_addr=None):
        """As ``run`` (``t`` from 0), and the summary of the same integration
        (the summary driver's, c/pdbfs_summary.c): (X, RunStatus, values (a
        list of len(SUMMARY_KEYS), NaN where undefined), summary code (0 ok, -1 when
        the run failed), note (its warnings or failure), kept). ``checked``: the
        caller (Simulator.run) has checked the arguments already, only their
        types and sizes are checked here (C checks them all again).
        ``keep`` with method "erk": the states on the grid are not computed
        now; X is None and ``kept`` (a KeptRun, None when the run failed) makes
        them when asked (c/pdbfs_run_trajectory.c); else ``kept`` is None.
        ``t_addr``: the address of ``t``'s data, where the caller has it
        (Simulator.run's plan: a read-only grid)."""
        if not checked:
            t = np.ascontiguousarray(t, dtype=float).ravel()
            x0 = np.ascontiguousarray(x0, dtype=float).ravel()
            p = np.ascontiguousarray(p, dtype=float).ravel()
            if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)) or \
                    not (rtol > 0 and atol > 0 and np.isfinite(rtol) and np.isfinite(atol)
                         and (max_step or 0.0) >= 0):
                raise ParameterError(f"rig {self.name}: rtol = {rtol}, atol = {atol}, "
                                     f"max_step = {max_step}, a grid from {t[0]} to {t[-1]}: "
                                     "not valid")
        elif t_addr is None:
            t = np.ascontiguousarray(t, dtype=float)
        # checked or not: the sizes, what C would read past the end of (C checks the rest
        # again); a grid with its address is the plan's, checked when the plan was made
        if len(x0) != self.nx or len(p) != self.np or method not in METHOD_CODES or \
                t_addr is None and (t.size < 2 or t[0] != 0.0 or t.dtype != np.float64
                                    or not t.flags.c_contiguous):
            raise ParameterError(f"rig {self.name}: run_summary needs {self.nx} start values, "
                                 f"{self.np} parameters, a strictly increasing grid from 0 "
                                 f"(float64) and a method of {', '.join(METHOD_CODES)}")
        keep = keep and method == "erk"
        X = None if keep else np.empty((self.nx, t.size))
        b = self._block()
        b.p[:] = p
        b.x0[:] = x0
        a = b.addr
        wall = time.perf_counter()
        code = self._run_summary(a[0], a[1], t.size, t_addr or t.ctypes.data,
                                 None if keep else X.ctypes.data,
                                 float(rtol), float(atol), METHOD_CODES[method],
                                 float(max_step or 0.0), int(max_num_steps), a[2], a[3], MSG_LEN,
                                 a[4], a[5], a[6], POINT_MSG_LEN * 2, a[7] if keep else None)
        wall = time.perf_counter() - wall
        i = b.info.tolist()
        status = RunStatus(int(code), i[0], int(i[1]), int(i[2]), int(i[3]), int(i[4]),
                           _text(b.msg), _stats(i[1], i[3], i[5], i[2], i[6], wall))
        handle = int(b.handle[0]) if keep else 0
        kept = KeptRun(self, handle, t, status.steps) if handle else None
        return X, status, b.out.tolist(), int(b.code[0]), _text(b.note, strip=False), kept

    def summaries(self, P, t_end, rtol, atol, method="adams", max_step=None,
                  max_num_steps=500000, with_stats=False):
        """Summaries of the parameter points ``P`` (n x np), each simulated
        from its own start values over [0, t_end]: (values (n x len(SUMMARY_KEYS),
        NaN where undefined), codes (n; 0 ok, RC_BAD_CROSSINGS, ...), messages
        (list of n str: the reason of a failure, or the warnings of a point that
        did not fail, e.g. a pulse cut off at t_end; "" if none)); with
        ``with_stats``, a fourth item: a list of n dicts of STAT_KEYS (steps and
        evaluations of the point's integration and of its refinements, the
        point's wall time)."""
        P = np.ascontiguousarray(np.atleast_2d(P), dtype=float)
        if P.shape[1] != self.np:
            raise ParameterError(f"rig {self.name}: points of {P.shape[1]} parameters given, "
                                 f"expected {self.np}")
        if method not in METHOD_CODES:
            raise ParameterError(f"unknown method {method!r}; choose one of {', '.join(METHOD_CODES)}")
        n = P.shape[0]
        out = np.empty((n, len(SUMMARY_KEYS)))
        codes = np.zeros(n, dtype=np.intc)
        msgs = ctypes.create_string_buffer(max(n, 1) * POINT_MSG_LEN)
        stats = np.zeros((n, NSTAT))
        failed = self._summaries(n, self.np, P.ctypes.data, float(t_end), float(rtol), float(atol),
                                 METHOD_CODES[method], float(max_step or 0.0), int(max_num_steps),
                                 out.ctypes.data, codes.ctypes.data, msgs, POINT_MSG_LEN,
                                 stats.ctypes.data)
        if failed < 0:
            raise PdbfsError(f"rig {self.name}: the summary driver refused its input")
        raw, messages, L = msgs.raw, [""] * n, POINT_MSG_LEN    # most points say nothing
        for i in np.flatnonzero(np.frombuffer(raw, np.uint8)[:n * L:L]):
            messages[i] = raw[i * L:(i + 1) * L].split(b"\0", 1)[0].decode(errors="replace")
        if with_stats:
            return out, codes, messages, [_stats(*row) for row in stats]
        return out, codes, messages

    def pulse_pairs(self, times, directions, above0, above1, t0, t1):
        """The summary driver's pairing of a pulse's crossings (c/pdbfs_pulse.c):
        (answer: 0 ok, 1 cut off, 2 crossings that do not alternate; duration,
        NaN unless ok; message)."""
        t = np.ascontiguousarray(times, dtype=float)
        dirs = np.ascontiguousarray(directions, dtype=np.intc)
        dur = np.zeros(1)
        msg = ctypes.create_string_buffer(POINT_MSG_LEN * 2)
        ans = self._pulse_pairs(t.size, t.ctypes.data, dirs.ctypes.data, int(bool(above0)),
                                int(bool(above1)), float(t0), float(t1), dur.ctypes.data, msg,
                                POINT_MSG_LEN * 2)
        return int(ans), float(dur[0]), msg.value.decode(errors="replace")


def compiled(dae) -> CompiledODE:
    """The CompiledODE of ``dae``, built (or loaded from the disk cache) once
    per DAE object."""
    c = dae.__dict__.get("_compiled_c")
    if c is None:
        c = dae.__dict__["_compiled_c"] = CompiledODE(dae)
    return c
