"""The impulse of a contact force, integrated by the solver on the solution.

A blow can last a few microseconds, less than the summary's output step: an
integral of the force's samples misses it or its split. Here the force is
integrated with the states instead: a quadrature of CVODES/IDAS in the
CasADi backend, the compiled driver's extra state in the compiled one
(c/pdbfs_batch.c: pdbfs_ode_q); both are left out of the error test, so the
states take the steps they take without it. Where the force is the only
force on a body, its impulse is that body's change of momentum, which the
integrator keeps to its tolerance. The summary (summary_run.py, summary.py)
carries it along its own solution and takes it at any instant by a short
integration from the output point before it, as Result.value_at does.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.errors import SolverError

from . import time_events as TE
from .failures import compiled_failure


def on_grid(sim, grid, x0, p, s: dict, force: str):
    """(states, algebraics, impulse) on ``grid`` from the state ``x0`` at
    ``grid[0]``, with the run's settings ``s`` (rtol, atol, method,
    max_step, max_num_steps, backend): the impulse (N s) of the output
    ``force`` from grid[0], a row like ``grid``."""
    grid = np.asarray(grid, float)
    if s.get("backend") == "c" and _compiled_force(sim, force):
        lib = sim.compiled()
        X, st = lib.run(grid, np.append(np.asarray(x0, float), 0.0), p, s["rtol"], s["atol"],
                        s["method"], s["max_step"], s["max_num_steps"])
        if not st.ok:
            raise compiled_failure(sim.dae.name, grid, st)
        if not np.all(np.isfinite(X)):
            sim._check_finite(grid, X)
        return X[:-1], np.zeros((0, grid.size)), X[-1]
    return _casadi(sim, grid, x0, p, s, force)


def at(sim, x, p, t0, t, s: dict, force: str) -> float:
    """The impulse of ``force`` over [t0, t] from the state ``x`` at t0."""
    if not t > t0:
        return 0.0
    return float(on_grid(sim, [t0, t], x, p, s, force)[2][-1])


def _compiled_force(sim, force) -> bool:
    """Whether the compiled library integrates this force's impulse (its contact force role)."""
    lib = sim.compiled()
    return bool(lib.nq) and (getattr(sim.dae, "signals", {}) or {}).get("contact_force") == force


def _casadi(sim, grid, x0, p, s, force):
    """From time event to time event (as time_events.pieces), each piece on
    the time-scaled integrator of its grid with the force as a quadrature."""
    dae = sim.dae
    nx, nz = dae.x.numel(), dae.z.numel()
    X, Z, Q = np.zeros((nx, grid.size)), np.zeros((nz, grid.size)), np.zeros(grid.size)
    edges = np.concatenate([[grid[0]], _switches(dae, p, grid), [grid[-1]]])
    x, total = np.asarray(x0, float), 0.0
    X[:, 0] = x
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        sub = np.concatenate([[a], grid[(grid > a) & (grid < b)], [b]])
        span = b - a
        z0, xdot0 = (sim.z_guess(p), None) if dae.is_ode else sim.consistent_start(a, x, p)
        F = _integrator(sim, s, force, (sub - a) / span, span,
                        None if xdot0 is None else span * xdot0)
        try:
            r = F(x0=x, p=np.concatenate([p, [a, span]]), z0=z0)
        except RuntimeError as err:
            first = str(err).splitlines()[0] if str(err) else "the integrator failed"
            raise SolverError(f"rig {dae.name}: the run with the impulse of {force} failed "
                              f"between t = {a:.6g} s and {b:.6g} s: {first}") from None
        Xs = r["xf"].full()
        Zs = r["zf"].full().reshape(nz, sub.size)
        Qs = total + r["qf"].full().reshape(-1)
        at_ = np.searchsorted(grid, sub)
        on = (at_ < grid.size) & (grid[np.minimum(at_, grid.size - 1)] == sub)
        on[0] = i == 0               # a switch point: the piece before wrote it
        X[:, at_[on]], Z[:, at_[on]], Q[at_[on]] = Xs[:, on], Zs[:, on], Qs[on]
        x, total = Xs[:, -1], float(Qs[-1])
    if not (np.all(np.isfinite(X)) and np.all(np.isfinite(Q))):
        sim._check_finite(grid, np.vstack([X, Q]))
    return X, Z, Q


def _switches(dae, p, grid) -> np.ndarray:
    """The time events inside the grid, those within roundoff of an output
    point moved onto it (as time_events.pieces)."""
    b = TE.breakpoints(dae, p, grid[0], grid[-1])
    if not b.size:
        return b
    tol = 64 * np.finfo(float).eps * max(abs(grid[0]), abs(grid[-1]))
    k = np.clip(np.searchsorted(grid, b), 1, grid.size - 1)
    near = np.where(np.abs(grid[k] - b) <= np.abs(grid[k - 1] - b), grid[k], grid[k - 1])
    b = np.unique(np.where(np.abs(near - b) <= tol, near, b))
    return b[(b > grid[0]) & (b < grid[-1])]


def _integrator(sim, s, force, tau, span, xdot0):
    """The integrator over [t0, t0 + h] on the output points ``tau`` in
    [0, 1] (parameters p, t0, h), the force as its quadrature, with the
    options of Simulator.integrator; kept per settings and tau, except an
    IDAS one with its start's der(x) (made per call). A ``max_step`` (s) is
    one of tau for this ``span``: the integrator is then this span's."""
    step = None if s["max_step"] is None else s["max_step"] / span
    key = ("impulse", force, np.asarray(tau, float).tobytes(), s["rtol"], s["atol"], s["method"],
           step, s["max_num_steps"])
    F = sim._cache.get(key)
    if F is not None and xdot0 is None:
        return F
    dae = sim.dae
    t0, h, t = ca.SX.sym("t0"), ca.SX.sym("h"), ca.SX.sym("tau")
    subs = lambda e: ca.substitute(e, dae.t, t0 + h * t)   # noqa: E731
    f = dae.y[dae.y_names.index(force)]
    spec = {"x": dae.x, "z": dae.z, "p": ca.vertcat(dae.p, t0, h), "t": t,
            "ode": h * subs(dae.ode), "alg": subs(dae.alg), "quad": h * subs(f)}
    opts = {"abstol": s["atol"], "reltol": s["rtol"], "max_num_steps": int(s["max_num_steps"]),
            "disable_internal_warnings": True, "show_eval_warnings": False}
    if step is not None:
        opts["max_step_size"] = step
    if dae.is_ode:
        opts["linear_multistep_method"] = s["method"]
    if xdot0 is not None:
        opts["init_xdot"] = [float(v) for v in xdot0]
    F = ca.integrator("impulse", "cvodes" if dae.is_ode else "idas", spec, float(tau[0]),
                      [float(v) for v in tau], opts)
    if xdot0 is None and len(sim._cache) < sim.CACHE_MAX:
        sim._cache[key] = F
    return F
