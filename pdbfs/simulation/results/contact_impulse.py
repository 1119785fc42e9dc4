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

import numpy as np

from .hermite import TRUST


def on_grid(sim, grid, x0, p, s: dict, force: str):
    """(states, algebraics, impulse) on ``grid`` from the state ``x0`` at
    ``grid[0]``, with the run's settings ``s`` (rtol, atol, method,
    max_step, max_num_steps, backend): the impulse (N s) of the output
    ``force`` from grid[0], a row like ``grid``."""
    split = getattr(sim, "by_segments", None)     # a run with inputs (driven.py): per segment
    if split is not None:
        return split(on_grid, grid, x0, p, s, force)
    grid = np.asarray(grid, float)
    if s.get("backend") == "c" and _compiled_force(sim, force):
        # the library integrates the impulse as the state after the rig's (compiled.run)
        X = sim.integrate_c(grid, np.append(np.asarray(x0, float), 0.0), p, s["rtol"], s["atol"],
                            s["method"], s["max_step"], s["max_num_steps"])
        return X[:-1], np.zeros((0, grid.size)), X[-1]
    return _casadi(sim, grid, x0, p, s, force)


def at(sim, x, p, t0, t, s: dict, force: str) -> float:
    """The impulse of ``force`` over [t0, t] from the state ``x`` at t0."""
    if not t - t0 > 8 * np.finfo(float).eps * max(abs(t), abs(t0)):
        return 0.0                  # closer than a solver can step (Simulator.step's rule)
    return float(on_grid(sim, [t0, t], x, p, s, force)[2][-1])


def force_role(dae) -> str | None:
    """The output playing the rig's contact force role, or None."""
    force = (getattr(dae, "signals", {}) or {}).get("contact_force")
    return force if force in dae.y_names else None


def impulse_at(R, Q, force: str, t: float) -> float:
    """The impulse at ``t`` of ``force`` on the solution of the Result ``R``,
    whose impulse on R.t is ``Q``: from the output point at or before t, on
    the force's Hermite cubic where that is trusted (hermite.py) and its
    integral over the whole interval is the solver's to a few times the
    run's rtol (else a blow lies between the two points), else by a short
    integration from there."""
    k = min(max(int(np.searchsorted(R.t, t, side="right")) - 1, 0), len(R.t) - 1)
    if t <= R.t[k] or k == len(R.t) - 1:
        return float(Q[k])
    got = R.curves.interval(force, k) if R.curves.data(force) is not None else None
    if got is not None and got[1]:
        h = R.t[k + 1] - R.t[k]
        part = lambda s: h * s * (got[0][0] + s * (got[0][1] / 2 + s * (got[0][2] / 3   # noqa: E731
                                                                      + s * got[0][3] / 4)))
        scale = R.curves.data(force)[2] * h
        # (the two agree only as well as the run's tolerance: a quadrature is not error-tested)
        if abs(part(1.0) - (Q[k + 1] - Q[k])) <= max(TRUST, 4 * R.settings["rtol"]) * scale:
            return float(Q[k] + part((t - R.t[k]) / h))
    return float(Q[k]) + at(R._sim, R._X[:, k], R.p, R.t[k], t, R.settings, force)


def _compiled_force(sim, force) -> bool:
    """Whether the compiled library integrates this force's impulse (its contact force role)."""
    return bool(sim.compiled().nq) and force_role(sim.dae) == force


def _casadi(sim, grid, x0, p, s, force):
    """From time event to time event, each state event located
    (time_events.pieces), the force a quadrature of the same steps and states."""
    return sim.located(grid, x0, p, s["rtol"], s["atol"], s["method"], s["max_step"],
                       s["max_num_steps"], force)
