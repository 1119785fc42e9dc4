"""One output of a rig as a function of chosen parameters, with exact
derivatives: the ground of calibration and design.

The rig is simulated once per parameter point on a fine uniform grid (5 us
by default) through the cached CVODES integrator; CasADi differentiates the
integrator (CVODES forward sensitivities), so each evaluation gives the
signal y, its time derivative dy/dt = (dy/dx) f + dy/dt|explicit, and the
sensitivities of both to every free parameter. Between the grid points a
cubic Hermite interpolant (scipy) of values and slopes gives y, dy/dt and
dy/dp at any time, e.g. a trace's own samples moved by a trigger shift: its
error at 5 us spacing is below 1e-6 of the peak where the signal is smooth,
and a few 1e-4 of it within the one step that holds a kink (oil column
going slack), far below a pressure sensor's noise.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError, SolverError
from pdbfs.simulation import Simulator
from pdbfs.simulation.analysis.driven_trajectory import driven_columns, driven_states
from pdbfs.simulation.analysis.trajectory import symbolic_states
from pdbfs.simulation.setup.initialize import refuse_solved_start
from pdbfs.simulation.setup.input_traces import drive_of
from pdbfs.simulation.setup.settings import default_atol

#: spacing of the fine grid, s
DT = 5e-6


def signal_of(dae, signal=None) -> str:
    """The output to use: ``signal``, else the rig's pressure role."""
    if signal is None:
        signal = (getattr(dae, "signals", {}) or {}).get("pressure")
        if signal is None:
            raise ParameterError(f"rig {dae.name} names no pressure signal; choose one with "
                                 "--signal NAME")
    if signal not in dae.y_names:
        import difflib
        close = difflib.get_close_matches(signal, dae.y_names, n=3)
        raise ParameterError(f"signal {signal!r} is not a variable of rig {dae.name}"
                             + (f"; did you mean {', '.join(close)}?" if close else ""))
    return signal


@dataclass
class Samples:
    """The signal on the grid: y, dy/dt and their sensitivities (n x k)."""

    t: np.ndarray
    y: np.ndarray
    ydot: np.ndarray
    dy: np.ndarray
    dydot: np.ndarray

    def __post_init__(self):
        from scipy.interpolate import CubicHermiteSpline
        stack = np.column_stack([self.y, self.dy])
        slope = np.column_stack([self.ydot, self.dydot])
        self.spline = CubicHermiteSpline(self.t, stack, slope, axis=0)

    def at(self, times):
        """(y, dy/dt, dy/dp) at ``times``; before t = 0 the rig is at rest
        in its start state (y(0), no slope)."""
        times = np.asarray(times, dtype=float)
        if times.size and times.max() > self.t[-1] * (1 + 1e-12):
            raise ParameterError(f"time {times.max():.6g} s is past the simulated "
                                 f"{self.t[-1]:.6g} s; raise t_end")
        tt = np.clip(times, 0.0, self.t[-1])
        v = self.spline(tt)
        d = self.spline(tt, 1)
        before = times < 0
        d[before] = 0.0
        return v[:, 0], d[:, 0], v[:, 1:]

    def slope_at(self, times):
        """(dy/dt, d(dy/dt)/dp, d2y/dt2) at ``times`` >= 0 (from the interpolant)."""
        tt = np.asarray(times, dtype=float)
        d = self.spline(tt, 1)
        return d[:, 0], d[:, 1:], self.spline(tt, 2)[:, 0]


#: most points of the fine grid, and of the coarse grid after it
MAX_FINE, MAX_COARSE = 40_000, 20_000


def model_grid(t_end, dt=DT, fine_until=None, coarse=MAX_COARSE) -> np.ndarray:
    """Spacing ``dt`` over [0, fine_until] (where the pulse is; at most
    MAX_FINE points), then ``coarse`` (at most MAX_COARSE) even steps to
    ``t_end``: the cost follows the pulse and the trace, not the horizon / dt."""
    fine_end = min(t_end, fine_until if fine_until is not None else t_end, MAX_FINE * dt)
    n = max(int(np.ceil(fine_end / dt)), 2) + 1
    fine = np.linspace(0.0, fine_end, n)
    if t_end <= fine_end * (1 + 1e-12):
        return fine
    m = int(max(1, min(coarse, MAX_COARSE, np.ceil((t_end - fine_end) / dt))))
    return np.concatenate([fine, np.linspace(fine_end, t_end, m + 1)[1:]])


def pulse_end(sim, p0, horizon, inputs=None) -> float | None:
    """Where the rig's pulse ends at the parameters ``p0`` (None if it has no
    pulse role or does not end within the look-ahead); ``inputs``: the rig's
    inputs (a Drive's ``given``), as simulate takes them."""
    from pdbfs.simulation.results.summary_run import summary_run
    if not (getattr(sim.dae, "signals", {}) or {}).get("pressure"):
        return None
    params = dict(zip(sim.dae.p_names, p0))
    if inputs:
        from pdbfs.simulation.run.driven import run_driven
        res = run_driven(sim, inputs, min(horizon, 0.02), 2001, params=params)
    else:
        res = sim.run(min(horizon, 0.02), 2001, params=params)
    return summary_run(res).t_done


class SignalModel:
    """``signal`` of ``rig`` on [0, t_end] as a function of the parameters
    ``targets`` (values in SI units); the others keep the values of ``p0``;
    ``inputs``: the rig's inputs (as simulate takes them), each segment of
    theirs integrated with its own values."""

    def __init__(self, sim: Simulator, signal: str, targets: list[str], t_end: float, p0,
                 *, dt: float = DT, rtol: float = 1e-8, atol: float | None = None,
                 fine_until: float | None = None, coarse: int = MAX_COARSE, progress=None,
                 inputs=None):
        dae = sim.dae
        if not dae.is_ode:
            raise ParameterError(f"rig {dae.name} keeps algebraic variables; fitting needs an "
                                 "ODE rig")
        if not (np.isfinite(t_end) and t_end > 0):
            raise ParameterError(f"t_end = {t_end}: must be a positive time in s")
        self.sim, self.signal, self.targets = sim, signal, list(targets)
        self.p0 = np.asarray(p0, dtype=float)
        self.grid = model_grid(t_end, dt, fine_until, coarse)
        n = self.grid.size
        index = {name: i for i, name in enumerate(dae.p_names)}
        y = dae.y[dae.y_names.index(signal)]
        ydot = ca.jtimes(y, dae.x, dae.ode) + ca.jacobian(y, dae.t)
        u = ca.MX.sym("u", len(targets))
        p = ca.MX(self.p0)
        for k, name in enumerate(targets):
            p[index[name]] = u[k]
        # the method "auto" picks at the start values: BDF for a stiff rig (a valve,
        # an orifice), whose sensitivities would cost Adams 50x the time
        refuse_solved_start(dae, "calibration and design")
        method = sim.resolve_method("auto", self.p0, sim.start_vector(self.p0), t_end)
        drive = drive_of(dae, inputs, self.grid)
        if drive is None:
            X, Z = symbolic_states(sim, self.grid, dae.function("start")(p), p, self.p0, rtol,
                                   default_atol(rtol, atol), method, None, targets)
            P = ca.repmat(p, 1, n)
        else:                  # the inputs' segments, each with its inputs as numbers
            p_start = ca.vertcat(p[:drive.u0], ca.DM(drive.p_at(self.p0, 0.0)[drive.u0:]))
            X, Z = driven_states(sim, self.grid, dae.function("start")(p_start), p, self.p0,
                                 drive, rtol, default_atol(rtol, atol), method, None, targets)
            P = driven_columns(p, drive, self.grid)
        rows = ca.Function("rows", [dae.t, dae.x, dae.z, dae.p], [ca.vertcat(y, ydot)]).map(n)
        Y = rows(ca.DM(self.grid.reshape(1, -1)), X, Z, P)
        self._f = ca.Function("signal", [u], [Y])
        self._fj = ca.Function("signal_sens", [u], [Y, ca.jacobian(ca.vec(Y), u)])
        self.evaluations = 0
        self.progress = progress          # called with the number of simulations so far

    def __call__(self, values, sens: bool = True) -> Samples:
        u = np.asarray(values, dtype=float)
        self.evaluations += 1
        if self.progress is not None:
            self.progress(self.evaluations)
        try:
            if sens:
                Y, J = (np.array(a) for a in self._fj(u))
            else:
                Y, J = np.array(self._f(u)), None
        except RuntimeError:
            where = ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.targets, u))
            raise SolverError(f"rig {self.sim.dae.name}: the solver failed at {where}") from None
        if not np.all(np.isfinite(Y)) or (J is not None and not np.all(np.isfinite(J))):
            where = ", ".join(f"{n} = {v:.6g}" for n, v in zip(self.targets, u))
            raise SolverError(f"rig {self.sim.dae.name}: the solution is not finite at {where}")
        n, k = len(self.grid), len(self.targets)
        if J is None:
            J = np.zeros((2 * n, k))
        J = J.reshape(n, 2, k)            # vec(Y) runs down the columns: (y, ydot) per time
        return Samples(self.grid, Y[0], Y[1], J[:, 0, :], J[:, 1, :])
