"""Time events: the switch times a rig declares (a valve opening or closing,
a prescribed motion's kink; ``dae.time_events``, functions of the
parameters). The CasADi path integrates from switch to switch, restarting
at each, so that no step can jump over one (the C drivers stop CVODE there
themselves, pdbfs/native/c/shared/pdbfs_cvode.c)."""
from __future__ import annotations

import numpy as np


def breakpoints(dae, p, t0, t1) -> np.ndarray:
    """The rig's time events strictly inside (t0, t1)."""
    b = dae.time_event_times(p)
    tol = 64 * np.finfo(float).eps * max(abs(t0), abs(t1))
    return np.unique(b[(b > t0 + tol) & (b < t1 - tol)])


def pieces(sim, grid, x0, p, rtol, atol, method, max_step, max_num_steps):
    """States and algebraics on ``grid``, integrated piece by piece between
    the time events (a new start at each, on the time-scaled integrator)."""
    grid = np.asarray(grid, float)
    b = breakpoints(sim.dae, p, grid[0], grid[-1])
    tol = 64 * np.finfo(float).eps * max(abs(grid[0]), abs(grid[-1]))
    k = np.clip(np.searchsorted(grid, b), 1, grid.size - 1)   # snap onto close grid points
    near = np.where(np.abs(grid[k] - b) <= np.abs(grid[k - 1] - b), grid[k], grid[k - 1])
    b = np.unique(np.where(np.abs(near - b) <= tol, near, b))
    edges = np.concatenate([[grid[0]], b, [grid[-1]]])
    nx, nz = sim.dae.x.numel(), sim.dae.z.numel()
    X, Z = np.zeros((nx, grid.size)), np.zeros((nz, grid.size))
    X[:, 0] = x0
    x, total = np.asarray(x0, float), {}
    for i, (a, c) in enumerate(zip(edges[:-1], edges[1:])):
        sub = np.concatenate([[a], grid[(grid > a) & (grid < c)], [c]])
        # pieces between switches have one-off grids: their integrators are not cached
        Xs, Zs = sim._shifted(sub, x, p, rtol, atol, method, max_step, max_num_steps,
                              keep=False)
        for key in ("steps", "rhs_evals", "jac_evals"):
            total[key] = total.get(key, 0) + sim._last_stats.get(key, 0)
        at = np.searchsorted(grid, sub)
        on = (at < grid.size) & (grid[np.minimum(at, grid.size - 1)] == sub)
        if i > 0:
            on[0] = False          # the switch point itself: the piece before wrote it
        X[:, at[on]], Z[:, at[on]] = Xs[:, on], Zs[:, on]
        if i == 0:
            Z[:, 0] = Zs[:, 0]
        x = Xs[:, -1]
    sim._last_stats = dict(sim._last_stats, **total, root_events=int(b.size))
    return X, Z
