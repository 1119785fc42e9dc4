"""The summary's own solution: the run integrated again on a grid of its
own, so that what the summary reports does not depend on the caller's
output grid or horizon.

The grid is fixed: spacing ``SUMMARY_STEP`` (or the rig's ``summary_step``)
from t = 0, in windows of ``WINDOW`` steps, each integrated from the end
state of the one before. A run is followed window by window until its
horizon, or, for rigs that strike once, until the pulse is over (the
pressure back under its level, the bodies apart): what happens later
changes no reported figure. A pulse still running at the horizon is
followed on (at most ``LOOK_AHEAD`` further) to say which horizon would
have held it. Peaks and crossings are then located on this solution
(Result.peak / crossings: Hermite interpolation where it is trusted, root
finding on the solution elsewhere). Rigs with a contact force also carry
its impulse along this solution (contact_impulse.py): the restitution's
impulses count a blow shorter than the grid's step whole.

When the caller's grid is this grid's first window (the default 2001 points
over 20 ms), its solution is reused: the default summary costs no
integration, and the rows it reads are computed in one pass
(Result.prefetch) and kept on the caller's Result.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pdbfs.errors import SolverError

from ..setup import limits
from .contact_impulse import on_grid

#: spacing of the summary's grid, s (a rig may set ``summary_step``)
SUMMARY_STEP = 1e-5
#: steps per window
WINDOW = 2000
#: most points a run followed to its horizon keeps (rigs that strike repeatedly;
#: about 1.3 GB for the drop rig): blows later than that are not listed, and
#: the summary says so
MAX_POINTS = 2_000_000
#: how far past the horizon an unfinished pulse is followed, in horizons (and windows at most)
LOOK_AHEAD = 20.0
MAX_WINDOWS_AHEAD = 100

PULSE_LEVEL = 0.01   # the pulse lasts while the pressure's rise exceeds 1 % of its peak rise


def pulse_level(base: float, peak: float) -> float:
    """The level above which the pressure is in the pulse: the start (static)
    pressure plus PULSE_LEVEL of the rise from it to the peak."""
    return base + PULSE_LEVEL * (peak - base)


def has_pulse(base: float, peak: float) -> bool:
    """A pulse is a rise above the start pressure beyond what the integrators
    leave of a body at rest (1e-5 of the start pressure, and 1 mPa: the
    explicit method lets a resting piston's pressure wander by 3e-6)."""
    return bool(peak - base > 1e-5 * abs(base) + 1e-3)


@dataclass
class SummaryRun:
    """The summary's own solution of a run, followed until the pulse is over."""

    trajectory: object          # a Result on the summary's grid, over [0, min(t_end, stop)]
    t_end: float                # the caller's horizon
    complete: bool | None       # the pulse ended inside the horizon (None: no pulse role)
    t_done: float | None        # where the pulse ended (also past the horizon), if it did
    looked_until: float         # how far the run was followed
    listed_until: float | None = None   # blows listed up to here only (MAX_POINTS)
    base: float = 0.0           # the start (static) pressure the pulse rises from
    pulse: bool | None = None   # the pressure rose above it inside the horizon (None: no pressure)
    peak_after: float = -np.inf  # the highest pressure on the run followed past the horizon
    #: the contact force's impulse on trajectory.t (N s, from t = 0): a function
    #: (integrated when first asked where the caller's run is reused), or None
    impulse: object = None


def summary_step(dae) -> float:
    """The summary solution's output step for this rig, s."""
    return float(getattr(dae, "summary_step", None) or SUMMARY_STEP)


def summary_run(res) -> SummaryRun:
    """The summary's solution of the run of ``res``: on a fixed grid from its start,
    followed past t_end (as far as the look-ahead allows) to see the pulse end."""
    Result = type(res)          # no import of result.py, which imports this module
    sim, s = res._sim, res.settings
    dae = sim.dae
    roles = getattr(dae, "signals", {}) or {}
    t_end = float(res.t[-1])
    follow_all = bool(roles.get("impact_indentation"))      # every blow counts
    h = summary_step(dae)
    listed_until = MAX_POINTS * h if follow_all and t_end > MAX_POINTS * h else None
    p_name, f_name = roles.get("pressure"), roles.get("contact_force")
    watch = [n for n in (p_name, f_name) if n]
    rows = [dae.y_names.index(n) for n in watch]
    limit = t_end + min(LOOK_AHEAD * t_end, MAX_WINDOWS_AHEAD * WINDOW * h)
    # a run with inputs is followed only as far as they were given (driven.py)
    limit = max(t_end, min(limit, getattr(sim, "known_until", np.inf)))

    ts, Xs, Zs, Qs = [], [], [], []
    x, t_last = res._X[:, 0], 0.0
    p_peak, t_done, t_busy = -np.inf, None, 0.0   # t_busy: last sample inside the pulse
    base, p_peak_in = None, -np.inf               # the start pressure; the peak inside the horizon
    p_after = -np.inf                             # the highest pressure past the horizon
    while True:
        k = int(np.floor(t_last / h + 1e-6)) + 1              # the next point of the fixed grid
        grid = np.concatenate([[t_last], h * np.arange(k, k + WINDOW)])
        end = t_end if t_last < t_end else limit
        if listed_until is not None and t_done is not None:
            end = min(end, listed_until)
        if grid[-1] >= end - 1e-6 * h:   # a grid point a rounding error short of the end is the end
            grid = np.append(grid[grid < end - 1e-6 * h], end)
        own = t_last == 0.0 and np.array_equal(grid, res.t)
        if own:
            X, Z = res._X, res._Z                                 # the caller's own run
            # every role's row, rate and the events in one pass: the summary reads them all
            res.prefetch([n for n in roles.values() if isinstance(n, str)])
            Q = res._impulse  # its impulse (None: integrated again if the restitution asks)
        else:
            try:
                X, Z, Q = _integrate(sim, grid, x, res.p, s, f_name)
                limits.check(sim, grid, X, Z, res.p, s)     # followed past t_end: still in range
            except SolverError as err:
                if grid[-1] <= t_end:
                    raise
                raise SolverError(f"{err} (the summary follows the pulse past t_end = "
                                  f"{t_end:g} s)") from None
        first = 0 if not ts else 1
        ts.append(grid[first:])
        Xs.append(X[:, first:])
        Zs.append(Z[:, first:])
        Qs.append(None if Q is None else Q[first:])
        t_last, x = float(grid[-1]), X[:, -1]
        if watch:
            if own:
                P = res[p_name] if p_name else None
                F = res[f_name] if f_name else None
            else:
                Y = np.atleast_2d(sim.outputs(grid, X, Z, res.p, rows))
                P = Y[watch.index(p_name)] if p_name else None
                F = Y[watch.index(f_name)] if f_name else None
            busy = np.zeros(grid.size, dtype=bool)
            if P is not None:
                base = float(P[0]) if base is None else base
                p_peak = max(p_peak, float(np.max(P)))
                if grid[0] < t_end:
                    p_peak_in = max(p_peak_in, float(np.max(P[grid <= t_end])))
                if grid[-1] > t_end:
                    p_after = max(p_after, float(np.max(P[grid > t_end])))
                if has_pulse(base, p_peak):
                    busy |= P >= pulse_level(base, p_peak)
            if F is not None:
                busy |= F > 0
            if busy.any():
                t_busy = float(grid[np.flatnonzero(busy)[-1]])
            rose = P is None or has_pulse(base, p_peak)
            over = rose and not busy[-1]
        else:
            over = rose = True
        if over and t_done is None:
            t_done = t_busy if t_busy > 0 else t_last
        if t_last >= t_end and not rose and not busy[-1]:
            break                # no pulse by the horizon: nothing to follow
        if t_last >= limit or (over and (t_last >= t_end or not follow_all)) or \
                (listed_until is not None and t_done is not None and t_last >= listed_until):
            break
    if len(ts) == 1 and own and ts[0][-1] <= t_end:
        traj = res          # the caller's run is the summary's solution: its rows serve both
        inside = np.ones(res.t.size, dtype=bool)
    else:
        t_all, X_all, Z_all = np.concatenate(ts), np.hstack(Xs), np.hstack(Zs)
        inside = t_all <= t_end
        traj = Result(sim, t_all[inside], res.p, X_all[:, inside], Z_all[:, inside], dict(s))
    impulse = (lambda: _impulse_rows(res, f_name, Qs)[inside]) if f_name else None
    pulse = has_pulse(base, p_peak_in) if p_name else None
    complete = (t_done is not None and t_done <= t_end and bool(pulse) if p_name else
                t_done is not None and t_done <= t_end) if watch else None
    return SummaryRun(traj, t_end, complete, t_done, t_last,
                      t_last if listed_until is not None and t_last < t_end else None,
                      base=base if base is not None else 0.0, pulse=pulse, peak_after=p_after,
                      impulse=impulse)


def _impulse_rows(res, force, Qs) -> np.ndarray:
    """The impulse from t = 0 over the windows (each window's from its start;
    None: the caller's run, integrated again on its grid with the impulse)."""
    rows, total = [], 0.0
    for Q in Qs:
        if Q is None:
            Q = on_grid(res._sim, res.t, res._X[:, 0], res.p, res.settings, force)[2]
        rows.append(total + Q)
        total = float(rows[-1][-1])
    return np.concatenate(rows)


def _integrate(sim, grid, x, p, s, force=None):
    """States, algebraics and, for a ``force``, its impulse (else None) on
    ``grid`` from x at grid[0], with the run's settings (one CasADi
    integrator, built once, serves every full window)."""
    if force:
        return on_grid(sim, grid, x, p, s, force)
    if s.get("backend") == "c":
        X = sim.integrate_c(grid, x, p, s["rtol"], s["atol"], s["method"], s["max_step"],
                            s["max_num_steps"])
        return X, np.zeros((0, grid.size)), None
    return sim.integrate_shifted(grid, x, p, s["rtol"], s["atol"], s["method"], s["max_step"],
                                 s["max_num_steps"]) + (None,)
