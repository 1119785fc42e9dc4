"""A run with inputs: integrated segment by segment, and the Simulator its
Result asks for everything afterwards.

Between two breakpoints of the inputs (input_traces.py) every input is
u + du (t - t_ref), entries of the DAE's parameter vector; each segment is
an ordinary run of the rig from the state the segment before ended in
(CVODE, IDAS or the explicit method restarted there, as at a time event),
on either back end, with the rig's own time events inside it as usual.
The Result of such a run holds a ``Driven`` as its simulator: the outputs,
rates and event indicators on a grid are evaluated with each point's own
inputs, and the integrations a Result does later (values between output
points, the summary's own solution, a contact force's impulse) go segment
by segment too, so that no figure of the run uses an input it was not given.
"""
from __future__ import annotations

import ctypes
import time

import numpy as np

from . import compiled as C
from .failures import compiled_failure

from ..setup import time_events as TE
from ..setup.initialize import solve_start
from ..setup.input_traces import drive_of
from ..results.result import Result
from ..setup.settings import MAX_NUM_STEPS, check_atol_scale, default_atol, default_rtol

_STAT_SUMS = ("steps", "rhs_evals", "jac_evals", "root_events")


class Driven:
    """A Simulator seen through one run's inputs (``drive``, a Drive)."""

    def __init__(self, sim, drive):
        self.base, self.drive, self.dae = sim, drive, sim.dae
        self._last_stats = {}

    def __getattr__(self, name):
        # what is not defined here would ignore the inputs: refused, never delegated
        raise AttributeError(f"{name}: not available on a run with inputs")

    @property
    def nx(self) -> int:
        """The rig's number of states."""
        return self.base.nx

    @property
    def state(self):
        """What the simulation layer keeps of the rig (state.py): the same for any inputs."""
        return self.base.state

    @property
    def known_until(self) -> float:
        """The end of the shortest trace given (inf: every input a number or
        held): the summary does not follow a pulse past it (summary_run.py)."""
        ends = [float(t[-1]) for t, _ in self.drive.traces if t.size > 1]
        return min(ends) if ends else np.inf

    def compiled(self, method: str | None = None):
        """The rig's compiled library (one with CVODE where ``method`` needs it)."""
        return self.base.compiled(method)

    # -- on a grid: each point with its own inputs ------------------------------------
    def p_at(self, p, t) -> np.ndarray:
        """p at the time ``t`` (its inputs there; t_ref = t)."""
        return self.drive.P_on(p, [t])[:, 0]

    def outputs(self, grid, X, Z, p, rows=None):
        """Outputs on ``grid``, each point with its inputs (Simulator.outputs)."""
        return self.base.outputs(grid, X, Z, self.drive.P_on(p, grid), rows)

    def rates_on(self, grid, X, Z, p, name):
        """The rate of ``name`` on ``grid``, each point with its inputs."""
        return self.base.rates_on(grid, X, Z, self.drive.P_on(p, grid), name)

    def events_on(self, grid, X, Z, p):
        """Event indicators on ``grid``, and a row of the inputs' kinks."""
        E = self.base.events_on(grid, X, Z, self.drive.P_on(p, grid))
        return np.vstack([E, self.drive.kink_row(grid)])     # the inputs' kinks too

    def rows_rates_events(self, grid, X, Z, p, names):
        """Outputs, rates and events on ``grid`` at once, each point with its inputs."""
        Y, rates, E = self.base.rows_rates_events(grid, X, Z, self.drive.P_on(p, grid), names)
        return Y, rates, np.vstack([E, self.drive.kink_row(grid)])

    # -- integrations, segment by segment ------------------------------------------------
    def _pieces(self, grid, x0, p, run, quad=False):
        """(X, Z, Q) on ``grid`` from x0: ``run(sub, x, p_piece)`` gives the
        arrays (X, Z[, Q]) of each segment on its grid ``sub``; a later
        segment writes a shared point (right-continuous: its z and
        outputs are the ones after the breakpoint). ``quad``: the third
        array is an integral from each segment's start, summed on."""
        grid = np.asarray(grid, float)
        X = Z = Q = None
        x, total, stats = np.asarray(x0, float), 0.0, {}
        seg = self.drive.segments(grid)
        for k in range(seg.count):
            a, c = seg.edges[k], seg.edges[k + 1]
            sub = np.concatenate([[a], grid[seg.lo[k]:seg.hi[k]], [c]])
            out = run(sub, x, seg.p_of(p, k))
            for k in _STAT_SUMS:
                stats[k] = stats.get(k, 0) + int(self.base._last_stats.get(k, 0))
            at = np.searchsorted(grid, sub)
            on = (at < grid.size) & (grid[np.minimum(at, grid.size - 1)] == sub)
            if X is None:
                X, Z = (np.zeros((a_.shape[0], grid.size)) for a_ in out[:2])
                Q = np.zeros(grid.size) if quad else None
            X[:, at[on]], Z[:, at[on]] = out[0][:, on], out[1][:, on]
            if quad:
                Q[at[on]] = total + out[2][on]
                total += float(out[2][-1])
            x = out[0][:, -1]
        self._last_stats = dict(self.base._last_stats, **stats)
        self.base._last_stats = self._last_stats
        return X, Z, Q

    def integrate_c(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps):
        """As Simulator.integrate_c."""
        grid = np.asarray(grid, float)
        seg = self.drive.segments(grid)
        if self.base.nx and seg.count > 1:        # every segment in one call of the driver
            return run_segments(self.base, seg, grid, x0, p, rtol, atol, method, max_step,
                                max_num_steps)

        def run(sub, x, q):
            X = self.base.integrate_c(sub, x, q, rtol, atol, method, max_step, max_num_steps)
            return X, np.zeros((0, sub.size))
        return self._pieces(grid, x0, p, run)[0]

    def integrate(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS):
        """As Simulator.integrate (the CasADi back end): (X, Z)."""
        base, s = self.base, max_num_steps

        def run(sub, x, q):
            if base.dae.x.numel() == 0:
                return base.prescribed(sub, q)
            return TE.pieces(base, sub, x, q, rtol, atol, method, max_step, s)[:2]
        return self._pieces(grid, x0, p, run)[:2]

    integrate_shifted = integrate

    def step(self, x, p, t0, h, rtol, atol, method, max_step=None, backend="casadi",
             max_num_steps=MAX_NUM_STEPS):
        """State and algebraics at t0 + h from x at t0 (Simulator.step's)."""
        def run(sub, xx, q):
            xe, ze = self.base.step(xx, q, float(sub[0]), float(sub[-1] - sub[0]), rtol, atol,
                                    method, max_step, backend=backend,
                                    max_num_steps=max_num_steps)
            return np.column_stack([xx, xe]), np.column_stack([np.zeros_like(ze), ze])
        X, Z, _ = self._pieces([t0, t0 + h], x, p, run)
        return X[:, -1], Z[:, -1]

    def by_segments(self, fn, grid, x0, p, s, force):
        """``fn(simulator, sub, x, p_piece, s, force)`` -> (X, Z, Q) (a contact
        force's impulse, contact_impulse.on_grid) over the segments."""
        return self._pieces(grid, x0, p, lambda sub, x, q: fn(self.base, sub, x, q, s, force),
                            quad=True)


_SEGMENTS: dict = {}     # library path -> its pdbfs_batch_run_segments (ctypes)


def run_segments(sim, seg, grid, x0, p, rtol, atol, method, max_step, max_num_steps):
    """The states on ``grid`` of a run over the Segments ``seg``, every
    segment integrated by the compiled driver in one call
    (native/c/library/pdbfs_segments.c): a trace of millions of samples
    costs its integration, not a call from Python per sample."""
    lib = sim.compiled(method)
    f = _SEGMENTS.get(str(lib.path))
    if f is None:
        f = ctypes.CDLL(str(lib.path)).pdbfs_batch_run_segments     # (the library loaded already)
        vp, ll, d = ctypes.c_void_p, ctypes.c_longlong, ctypes.c_double
        f.restype = ctypes.c_int
        f.argtypes = [ll, ll, vp, vp, ll, vp, vp, ll, ll, ll, vp, vp, d, d, ctypes.c_int, d, ll,
                      vp, ctypes.c_char_p, ll]
        _SEGMENTS[str(lib.path)] = f
    x0 = np.ascontiguousarray(x0, dtype=float)
    p = np.ascontiguousarray(p, dtype=float)
    grid = np.ascontiguousarray(grid, dtype=float)
    edges, coef = np.ascontiguousarray(seg.edges), np.ascontiguousarray(seg.coef)
    X = np.empty((x0.size, grid.size))
    info = np.zeros(C.INFO_N)
    msg = ctypes.create_string_buffer(C.MSG_LEN)
    wall = time.perf_counter()
    code = f(x0.size, p.size, p.ctypes.data, x0.ctypes.data, seg.count, edges.ctypes.data,
             coef.ctypes.data, seg.inputs, seg.rows[0], grid.size, grid.ctypes.data,
             X.ctypes.data, float(rtol), float(atol), C.METHOD_CODES[method],
             float(max_step or 0.0), int(max_num_steps), info.ctypes.data, msg, C.MSG_LEN)
    st = C.RunStatus(int(code), float(info[0]), int(info[1]), int(info[2]), int(info[3]),
                     int(info[4]), msg.value.decode(errors="replace").strip(),
                     C._stats(info[1], info[3], info[5], info[2], info[6],    # (as lib.run's)
                              time.perf_counter() - wall))
    if not st.ok:
        raise compiled_failure(sim.dae, grid, st)
    stats = dict(st.stats)
    stats.pop("wall_time", None)
    sim._last_stats = stats
    if not np.isfinite(np.add.reduce(X, axis=None)):
        sim._check_finite(grid, X)
    return X


def run_driven(sim, inputs, t_end, n_out, *, t_out=None, params=None, start=None, rtol=None,
               atol=None, method="auto", max_step=None, max_num_steps=MAX_NUM_STEPS, backend="auto",
               initial=None):
    """simulate() with ``inputs``: every argument checked first, then the run
    segment by segment (a Result whose simulator is a Driven)."""
    backend, grid, _ = sim.run_settings(t_end, n_out, t_out, rtol, atol, method, max_step,
                                        max_num_steps, backend, initial)
    drive = drive_of(sim.dae, inputs, grid)
    p = sim.param_vector(params)
    if drive is None:          # nothing given: every input held at its start, as run() does
        return sim.run(t_end, n_out, t_out=t_out, params=params, start=start, rtol=rtol,
                       atol=atol, method=method, max_step=max_step,
                       max_num_steps=max_num_steps, backend=backend, initial=initial)
    p0 = drive.p_at(p, float(grid[0]))            # the inputs of the first segment
    x0 = sim.start_vector(p0, start)
    init = x0
    if initial is not None or sim._needs_solving():
        x0, init = solve_start(sim, p0, x0, initial, float(grid[0]))
    check_atol_scale(sim.dae, x0, atol)
    method = sim.resolve_method(method, p0, x0, grid[-1] - grid[0], backend)
    rtol = default_rtol(method, rtol)
    atol = default_atol(rtol, atol)
    wall = time.perf_counter()
    driven = Driven(sim, drive)
    if backend == "c":
        X = driven.integrate_c(grid, x0, p0, rtol, atol, method, max_step, max_num_steps)
        Z = np.zeros((0, grid.size))
    else:
        X, Z = driven.integrate(grid, x0, p0, rtol, atol, method, max_step, max_num_steps)
    stats = dict(driven._last_stats, wall_time=time.perf_counter() - wall, backend=backend,
                 segments=drive.segments(grid).count)
    drive.release()
    settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                "max_num_steps": max_num_steps, "backend": backend}
    res = Result(driven, grid, p0, X, Z, settings, stats, initial=init, own_stats=True)
    res._drive = drive                     # the inputs travel with the Result (sweeps)
    return res
