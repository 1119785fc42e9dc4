"""The ranges a rig's variables are declared valid in (``Variable(min=,
max=)``: a chamber's volume stays above 0). Past such a bound the
component's equations describe nothing physical (a negative volume), so a
run that reaches one stops there with a SolverError naming the variable,
the bound and the time, instead of giving numbers past it.

The compiled drivers check every step they record (c/pdbfs_record.c) and
answer RC_LIMIT with the limit's index and the time, located on the step
(:func:`from_c` makes the message); a run on an output grid (CasADi, or the
compiled run without a record) is checked here on its grid (:func:`check`),
the crossing located on the solution between the two output times around
it. A solver that fails as a variable nears its bound (a chamber's volume
going to 0 makes its pressure equation singular) is told so too.
"""
from __future__ import annotations

import re

import numpy as np

from pdbfs.errors import PdbfsError, SolverError
from pdbfs.modelling import quantity

#: a compiled run's code for a limit reached (c/pdbfs_record.h RC_LIMIT)
RC_LIMIT = 8
#: a failure at a state where a limit is within this fraction of its value at
#: the start is put down to the bound (c/pdbfs_record.h LIMIT_NEAR)
NEAR = 1e-3

_C_TEXT = re.compile(r"limit (\d+) (crossed|near) at t = (\S+)(?: value (\S+))?")


def count(dae) -> int:
    """How many limits the rig declares (cached on the DAE)."""
    return dae.cached("limits_n", lambda: len(dae.limits))


def message(dae, j: int, t: float, value: float | None = None) -> str:
    """The SolverError text of limit ``j`` reached at ``t`` (``value``: the
    variable's distance from its bound where a solver failed short of it)."""
    v, kind, bound = dae.limits[j]
    beyond = f": {v.beyond}" if v.beyond else ""
    what = f"{v.name} ({v.description})"
    if value is not None:
        at = bound + value if kind == "min" else bound - value
        side = "minimum" if kind == "min" else "maximum"
        return (f"rig {dae.name}: the solver failed at t = {t:.6g} s as {what} reached its "
                f"{side} {quantity(bound, v.unit)} ({quantity(at, v.unit, '.3g')} there){beyond}")
    verb = "fell below its minimum" if kind == "min" else "rose above its maximum"
    return (f"rig {dae.name}: {what} {verb} {quantity(bound, v.unit)} at t = {t:.6g} s, where the run "
            f"stops (past it the rig's equations do not hold){beyond}")


def from_c(dae, text: str) -> str | None:
    """The message of a compiled driver's RC_LIMIT text, or None if it is not one."""
    m = _C_TEXT.search(text or "")
    if m is None or int(m.group(1)) >= count(dae):
        return None
    value = float(m.group(4)) if m.group(2) == "near" and m.group(4) else None
    return message(dae, int(m.group(1)), float(m.group(3)), value)


def check(sim, grid, X, Z, p, s) -> None:
    """Raise a SolverError if the run (states ``X``, algebraics ``Z`` on
    ``grid``, parameters ``p``, settings ``s`` as a Result's) leaves a
    variable's declared range: at the first output time outside it, the
    crossing located on the solution from the output time before."""
    dae = sim.dae
    if X is None or not count(dae):
        return
    n = grid.size
    g = np.asarray(dae.function("limits").map(n)(np.reshape(grid, (1, n)), X, Z,
                                                 np.repeat(np.reshape(p, (-1, 1)), n, axis=1)))
    with np.errstate(invalid="ignore"):
        out = g < 0
    cols = np.flatnonzero(out.any(axis=0))
    if not cols.size:
        return
    k = int(cols[0])
    rows = np.flatnonzero(out[:, k])
    if k == 0:
        raise SolverError(message(dae, int(rows[0]), float(grid[0])))
    t_cross = {int(j): _crossing(sim, grid, X, p, s, k, int(j), g) for j in rows}
    j = min(t_cross, key=t_cross.get)
    raise SolverError(message(dae, j, t_cross[j]))


def _crossing(sim, grid, X, p, s, k, j, g) -> float:
    """Where limit j crosses 0 between grid[k-1] (inside) and grid[k] (out),
    on the solution integrated from grid[k-1]; grid[k] where that fails."""
    from scipy.optimize import brentq
    dae = sim.dae
    a, b = float(grid[k - 1]), float(grid[k])
    f = dae.function("limits")

    def value(t):
        if t <= a:
            return float(g[j, k - 1])
        if t >= b:
            return float(g[j, k])
        x, z = sim.step(X[:, k - 1], p, a, t - a, s["rtol"], s["atol"], s["method"],
                        s["max_step"], backend=s.get("backend", "casadi"),
                        max_num_steps=s.get("max_num_steps", 500000))
        return float(np.asarray(f(t, x, z, p)).ravel()[j])

    if not g[j, k - 1] >= 0:       # NaN before: nothing to locate
        return b
    try:
        return float(brentq(value, a, b, xtol=1e-14 * max(abs(b), 1e-300), rtol=1e-12))
    except (PdbfsError, RuntimeError, ValueError, ArithmeticError):
        return b


def near(dae, t, x, z, p) -> str | None:
    """The message of a solver failure at ``(t, x, z)`` where a limit is
    within NEAR of its value at the start (the failure's likely cause), or None."""
    if not count(dae):
        return None
    import casadi as ca
    f = dae.function("limits")
    x0 = np.asarray(dae.function("start")(p), float).ravel()
    z0 = np.asarray(ca.Function("z0", [dae.p], [dae.z0])(p), float).ravel() \
        if dae.z.numel() else np.zeros(0)
    g0 = np.asarray(f(0.0, x0, z0, p), float).ravel()
    g = np.asarray(f(t, x, np.zeros(0) if z is None else z, p), float).ravel()
    for j in range(g.size):
        if g0[j] > 0 and g[j] < NEAR * g0[j]:
            return message(dae, j, float(t), float(g[j]))
    return None
