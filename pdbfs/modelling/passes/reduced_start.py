"""Start values of states that index reduction made algebraic.

Such a variable is computed from the constraint it is tied by; a declared
start value (a number, or a parameter expression such as a Mass's ``s0``)
cannot be used, so it must agree with what the constraint gives, at the
default parameter values when the rig compiles and again whenever
parameters are set (``--set m2.v0=...``, or a start of the body that
drives it), or the user's value
would be ignored silently. A variable with no declared start is simply
solved for.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError, ParameterError

from ..symbols import quantity


def record(dae, dropped, constraints):
    """Keep (name, unit, start expression of p) of the dropped states that
    declare a start, and the constraints' labels, on the DAE."""
    dae.reduced_starts = [(v.name, v.unit, ca.SX(v.start)) for v in dropped
                          if v.start is not None]
    dae.reduced_by = list(dict.fromkeys(constraints))


def check(dae, p, error=ModelError):
    """Raise ``error`` (one line) naming the first reduced state whose
    declared start differs from what the constraint gives at parameters p."""
    starts = getattr(dae, "reduced_starts", None)
    if not starts:
        return
    p = np.asarray(p, dtype=float)
    x0 = np.array(dae.function("start")(p)).ravel()
    z = np.array(ca.Function("z0", [dae.p], [dae.z0])(p)).ravel()
    if not dae.is_ode:
        rf = dae.cached("z0_rootfinder", lambda: ca.rootfinder(
            "z0", "newton", {"x": dae.z, "p": ca.vertcat(dae.t, dae.x, dae.p), "g": dae.alg},
            {"error_on_fail": False}))
        z = np.array(rf(z, np.concatenate([[0.0], x0, p]))).ravel()
    y = np.array(dae.function("out")(0.0, x0, z, p)).ravel()
    at = {n: k for k, n in enumerate(dae.y_names)}
    mine = np.array(ca.Function("s", [dae.p], [ca.vertcat(*[e for _, _, e in starts])])(p)).ravel()
    where = "; ".join(dae.reduced_by) or "a constraint"
    for (name, unit, _), a in zip(starts, mine):
        b = y[at[name]]
        if np.isfinite(b) and abs(a - b) > 1e-8 * (1.0 + abs(a) + abs(b)):
            raise error(
                f"{name} starts at {quantity(a, unit)}, but the constraint that index reduction solves "
                f"for it ({where}) gives {quantity(b, unit)} at the start: its start is not free; give "
                "start values that satisfy the constraint")
