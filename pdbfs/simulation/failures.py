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
    if st.code in (-8, -9, -10, -11):       # CV_RHSFUNC_FAIL ... CV_UNREC_RHSFUNC_ERR
        cause = ("the right-hand side became NaN or infinite (a force blowing up, or a "
                 "parameter out of range)")
    else:
        cause = causes.get(st.code, "CVODE failed")
    who = "explicit Runge-Kutta" if str((getattr(st, "stats", None) or {}).get("method", "")) \
        .startswith("erk") else "CVODE"
    detail = f" ({who}: {st.message})" if st.message else ""
    return SolverError(f"rig {name}: the solver failed after t = {st.t_reached:.6g} s "
                       f"(of {grid[-1]:.6g} s): {cause}{detail}")


def walk_failure(sim, grid, x0, p, rtol, atol, method, max_step, err, max_num_steps):
    """Walk the grid interval by interval to report where the solver stopped."""
    x, t_ok = x0, grid[0]
    for a, b in zip(grid[:-1], grid[1:]):
        try:
            x, _ = sim.step(x, p, a, b - a, rtol, atol, method, max_step,
                            max_num_steps=max_num_steps)
        except RuntimeError:
            break
        if not np.all(np.isfinite(x)):
            break
        t_ok = b
    reason = str(err).strip().splitlines()[-1] if str(err).strip() else repr(err)
    for code, cause in CAUSES.items():
        if code in str(err):
            reason = cause
            break
    where = (f"after t = {t_ok:.6g} s (of {grid[-1]:.6g} s)" if t_ok < grid[-1] else
             f"before t = {grid[-1]:.6g} s (a retry interval by interval got through, so "
             "the rig is at the edge of what these settings can do)")
    return SolverError(f"rig {sim.dae.name}: the solver failed {where}: {reason}")
