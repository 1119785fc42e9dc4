"""What a failed integration most likely means, for SolverError messages."""
from __future__ import annotations

import numpy as np

from pdbfs.errors import ParameterError, SolverError

from . import compiled as C

CAUSES = {   # CVODES/IDAS failure -> the likely cause, for SolverError messages
    "TOO_MUCH_WORK": "too many steps: the solution may blow up (a force or parameter out of "
                     "range), or the rig is very stiff (try method='bdf')",
    "CONV_FAIL": "the corrector did not converge: stiffness or a discontinuity; try "
                 "method='bdf' or a max_step",
    "ERR_FAIL": "the error test failed repeatedly: a discontinuity or a parameter far out of "
                "range",
    "TOO_CLOSE": "the time span is too short",
    "IDACalcIC": "IDAS found no consistent start for the algebraic variables: a nonlinear "
                 "block that is singular at the start (e.g. power-law springs in series have "
                 "zero stiffness at rest, where Newton cannot converge)",
}


def compiled_failure(name, grid, st) -> Exception:
    """The error to raise for a failed run of the compiled driver (a RunStatus)."""
    if st.code == C.RC_BAD_INPUT:
        return ParameterError(f"rig {name}: the compiled solver refused its input: {st.message}")
    causes = {
        C.RC_TOO_MUCH_WORK: CAUSES["TOO_MUCH_WORK"],
        C.RC_NOT_FINITE: "the solution became NaN or infinite; check parameter values (a "
                         "stiffness or exponent far out of range?)",
        -1: CAUSES["TOO_MUCH_WORK"],                              # CV_TOO_MUCH_WORK
        -2: "the tolerances are too small for double precision",  # CV_TOO_MUCH_ACC
        -3: CAUSES["ERR_FAIL"],                                   # CV_ERR_FAILURE
        -4: CAUSES["CONV_FAIL"],                                  # CV_CONV_FAILURE
        -27: CAUSES["TOO_CLOSE"],                                 # CV_TOO_CLOSE
    }
    method = str((getattr(st, "stats", None) or {}).get("method", ""))
    who = "explicit Runge-Kutta" if method.startswith("erk") else "CVODE"
    if st.message == "out of memory":       # the record of the run's steps outgrew it
        return SolverError(
            f"rig {name}: the run ran out of memory after t = {st.t_reached:.6g} s (of "
            f"{grid[-1]:.6g} s, {st.steps} steps): it keeps every step of its solution for "
            "its summary; ask for a shorter t_end")
    if st.code in (-8, -9, -10, -11):       # CV_RHSFUNC_FAIL ... CV_UNREC_RHSFUNC_ERR
        cause = ("the right-hand side became NaN or infinite (a force blowing up, or a "
                 "parameter out of range)")
    else:
        cause = causes.get(st.code, f"{who} failed")
    if method.startswith("bdf"):             # already the method the hints suggest
        cause = cause.replace(" (try method='bdf')", "").replace("method='bdf' or ", "")
    detail = f" ({who}: {st.message})" if st.message else ""
    if who != "CVODE" and "method='bdf'" not in cause:   # an explicit method and a stiff rig
        detail += "; if the rig is stiff there, try method='bdf'"
    return SolverError(f"rig {name}: the solver failed after t = {st.t_reached:.6g} s "
                       f"(of {grid[-1]:.6g} s): {cause}{detail}")


def walk_failure(sim, grid, x0, p, rtol, atol, method, max_step, err, max_num_steps):
    """Walk the grid interval by interval, then the failing interval by
    halving steps, to report the time the solver really reached (not the
    last output point), and what is wrong there."""
    x, z, t_ok = x0, None, grid[0]
    step = lambda x, a, h: sim.step(x, p, a, h, rtol, atol, method, max_step,
                                    max_num_steps=max_num_steps)
    for a, b in zip(grid[:-1], grid[1:]):
        try:
            x1, z1 = step(x, a, b - a)
        except RuntimeError:
            # a step that fails fails faster with a small budget; the halving
            # still closes in on where the solver stops
            short = lambda x, a, h: sim.step(x, p, a, h, rtol, atol, method, max_step,
                                             max_num_steps=min(max_num_steps, 2000))
            t_r, x_r, z_r = _reached(short, x, z, a, b)
            if t_r < b:
                t_ok, x, z = t_r, x_r, z_r
                break
            x1, z1 = x_r, z_r            # in shorter steps it got through: walk on
        if not np.all(np.isfinite(x1)):
            break
        x, z, t_ok = x1, z1, b
    reason = str(err).strip().splitlines()[-1] if str(err).strip() else repr(err)
    for code, cause in CAUSES.items():
        if code in str(err):
            reason = cause
            break
    if t_ok < grid[-1]:
        undetermined = _undetermined(sim.dae, t_ok, x, z, p)
        if undetermined:
            reason = undetermined
    where = (f"after t = {t_ok:.9g} s (of {grid[-1]:.6g} s)" if t_ok < grid[-1] else
             f"before t = {grid[-1]:.6g} s (a retry interval by interval got through, so "
             "the rig is at the edge of what these settings can do)")
    return SolverError(f"rig {sim.dae.name}: the solver failed {where}: {reason}")


def _reached(step, x, z, a, b):
    """(time, state, algebraic) the solver reaches from a towards b, to a
    millionth of the interval, by steps halved where they fail."""
    t, h = a, 0.5 * (b - a)
    while h > 1e-6 * (b - a) and b - t > 1e-9 * (b - a):
        h_try = min(h, b - t)
        try:
            x1, z1 = step(x, t, h_try)
        except RuntimeError:
            h *= 0.5
            continue
        if not np.all(np.isfinite(x1)):
            h *= 0.5
            continue
        x, z, t = x1, z1, t + h_try
    return (b if b - t <= 1e-9 * (b - a) else t), x, z


def _undetermined(dae, t, x, z, p):
    """Why the algebraic equations of a reduced rig fail at t, if they do:
    their Jacobian in the algebraic variables has become singular (far below
    what it is at the start), so those variables are not determined - joined
    volumes that all cavitate, whose vapour volumes no equation divides.
    None for an ODE rig or a regular Jacobian."""
    if dae.is_ode or z is None or not np.size(z):
        return None
    import casadi as ca
    f = dae.__dict__.get("_alg_jacobian")
    if f is None:
        f = dae.__dict__["_alg_jacobian"] = ca.Function(
            "alg_jac", [dae.t, dae.x, dae.z, dae.p], [ca.densify(ca.jacobian(dae.alg, dae.z))])
    J = np.atleast_2d(np.array(f(t, x, z, p), dtype=float))
    x0 = np.array(dae.function("start")(p)).ravel()
    J0 = np.atleast_2d(np.array(f(0.0, x0, ca.Function("z0", [dae.p], [dae.z0])(p), p),
                                dtype=float))
    sv, sv0 = np.linalg.svd(J, compute_uv=False), np.linalg.svd(J0, compute_uv=False)
    if not (np.all(np.isfinite(sv)) and sv0.min() > 0 and sv.min() < 1e-3 * sv0.min()):
        return None
    weak = [dae.z_names[k] for k in range(J.shape[1])
            if np.linalg.norm(J[:, k]) < 1e-3 * max(np.linalg.norm(J0[:, k]), 1e-300)]
    weak = weak or dae.z_names
    by = "; ".join(getattr(dae, "reduced_by", []) or []) or "the constraints index reduction made"
    if all(n.endswith(".p_law") for n in weak):
        y = dict(zip(dae.y_names, np.array(dae.function("out")(t, x, z, p)).ravel()))
        vols = [n[:-len(".p_law")] for n in dae.x_names + dae.z_names if n.endswith(".p_law")]
        at = ", ".join(f"{v}.p = {y[v + '.p']:.6g} Pa" for v in vols if v + ".p" in y)
        return (f"the joined volumes {', '.join(vols)} all cavitate ({at}): their vapour "
                f"volumes are not determined (the constraint between their pressures, reduced by "
                f"differentiation, no longer determines {', '.join(weak)}); "
                "no solver setting helps: join them through a resistance (an Orifice or "
                "LaminarLeak), or model them as one Volume")
    return (f"the algebraic equations no longer determine {', '.join(weak)} (their Jacobian "
            f"is singular there; index reduction solved {by} for them); no solver setting "
            "helps: the rig needs a compliance or resistance where that constraint holds")
