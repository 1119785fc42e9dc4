"""A rig's simulation as a CasADi Function of its parameters.

    f = trajectory_function(paper_rig(), ["oil.pressure"], inputs=["oil.k", "seal.c"])
    Y = f([2.228e8, 2.556e4])                        # 1 x n_out
    J = casadi.Function("J", [p := casadi.MX.sym("p", 2)], [casadi.jacobian(f(p), p)])

The Function wraps the same cached CVODES/IDAS integrator as ``simulate``;
CasADi differentiates it (forward sensitivities of SUNDIALS) and evaluates
it on many points (``f.map``): the ground for calibration and inverse
design on the same DAE.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError
from .initialize import refuse_solved_start
from .simulator import MAX_NUM_STEPS, Simulator


def trajectory_function(model, outputs, t_end: float = 0.02, n_out: int = 2001, *,
                        t_out=None, inputs=None, params=None, rtol: float = 1e-8,
                        atol: float = 1e-10, method: str = "auto",
                        max_step: float | None = None) -> ca.Function:
    """casadi.Function ``p -> y``: ``outputs`` (dotted names) on the output
    grid, one row each, as functions of the parameters named in ``inputs``
    (all free parameters if None, in ``dae.p_names`` order). Parameters not
    among the inputs keep their defaults, or the values in ``params``."""
    sim = Simulator.of(model)
    dae = sim.dae
    grid = sim.grid(t_end, n_out, t_out)
    index = {n: i for i, n in enumerate(dae.y_names)}
    if isinstance(outputs, str):
        outputs = [outputs]
    missing = [n for n in outputs if n not in index]
    if missing or not outputs:
        raise ParameterError(f"trajectory_function: unknown output(s) {', '.join(missing)} of "
                             f"rig {dae.name}" if missing else "trajectory_function: no outputs")
    inputs = list(dae.p_names if inputs is None else inputs)
    p_index = {n: i for i, n in enumerate(dae.p_names)}
    unknown = [n for n in inputs if n not in p_index]
    if unknown:
        sim.param_vector({unknown[0]: 0.0})   # raises the usual error, with suggestions
    p0 = sim.param_vector(params)
    refuse_solved_start(dae, "trajectory_function")

    u = ca.MX.sym("p", len(inputs))
    p = ca.MX(p0)                         # dense MX column of the full parameter vector
    for k, name in enumerate(inputs):
        p[p_index[name]] = u[k]
    x0 = dae.function("start")(p)
    method = sim.resolve_method(method, p0, dae.function("start")(p0).full().ravel(),
                                grid[-1] - grid[0])
    F = sim.integrator(grid, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS)
    r = F(x0=x0, p=p, z0=sim.z_guess(p0))
    n = len(grid)
    rows = ca.vertcat(*[dae.y[index[name]] for name in outputs])
    out = ca.Function("out", [dae.t, dae.x, dae.z, dae.p], [rows]).map(n)
    y = out(ca.DM(np.asarray(grid).reshape(1, -1)), r["xf"], r["zf"], ca.repmat(p, 1, n))
    return ca.Function("trajectory", [u], [y], ["p"], ["y"])
