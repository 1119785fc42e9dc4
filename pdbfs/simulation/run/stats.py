"""Solver statistics of a run under one set of names for both back ends
(Result.stats): steps, rhs_evals, jac_evals, root_events, method, and,
added by the caller, wall_time (s) and backend."""
from __future__ import annotations


def casadi_stats(raw: dict, method: str) -> dict:
    """The solver statistics of one casadi integrator call, under pdbfs's
    names (the events located between calls are counted by the caller,
    setup/time_events.py)."""
    return {"steps": int(raw.get("nsteps", 0)), "rhs_evals": int(raw.get("nfevals", 0)),
            "jac_evals": int(raw.get("n_call_jacF", 0)), "root_events": 0, "method": method}
