"""The solved start as a C-generatable CasADi Function of p: the FMU's
``pdbfs_start`` for rigs whose start is solved (free states, initial
equations; pdbfs.modelling.initialization), so that an FMU solves it in
its initialization mode, at the parameters it is given.

Newton with the exact Jacobian from the declared start values, damped by
step halving on the residual (plain Newton, e.g. CasADi's ``fast_newton``,
oscillates for ever on an orifice's square-root law; CasADi's ``newton``
cannot be generated as C), as ``MAX_ITER`` iterations of one CasADi
Function looped by ``mapaccum`` (compact C); the unknowns scaled by their
guesses' sizes and the equations by the size of their terms at the default
parameters. Where the scaled residual is not below ``RESIDUAL_TOL`` at
the end, the start is not finite: the FMU's ExitInitializationMode refuses
non-finite start values with an error, never a wrong start.

The initial equations are taken at t = 0 (the rigs' start time).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from pdbfs.modelling.initialization import square_start, start_residual, start_system

MAX_ITER = 50
RESIDUAL_TOL = 1e-8


def solved_start_function(dae, name: str = "pdbfs_start") -> ca.Function:
    """The CasADi Function ``name``: p -> the solved start x0 (not finite where Newton failed)."""
    free, eqs, names = start_system(dae)
    square_start(dae, free, eqs, names)       # as many equations as unknowns, or a ModelError
    w, xg, G = start_residual(dae, free, eqs)
    nw = w.numel()
    p = dae.p
    x_guess = dae.x0
    z_guess = dae.z0 if dae.z0 is not None else ca.SX(0, 1)
    w_guess = ca.vertcat(*[x_guess[i] for i in free], z_guess)
    # scales at the default parameters: unknowns by their guesses, equations
    # by the size of their terms there
    p0 = dae.p_default()
    w0 = np.asarray(ca.Function("w0", [p], [w_guess])(p0), float).ravel()
    d = np.maximum(np.abs(w0), 1e-8)
    Jfun = ca.Function("J", [w, xg, p], [ca.substitute(ca.jacobian(G, w), dae.t, 0.0)])
    x00 = np.asarray(ca.Function("x0", [p], [x_guess])(p0), float).ravel()
    J0 = np.asarray(Jfun(w0, x00, p0), float).reshape(nw, nw)
    r = np.abs(J0) @ d
    r = np.where(np.isfinite(r) & (r > 0), r, 1.0)
    u = ca.SX.sym("u", nw)
    par = ca.vertcat(xg, p)
    Gs = ca.substitute(G, ca.vertcat(dae.t, w), ca.vertcat(0.0, d * u)) / r
    loop = _damped_newton(ca.Function("G", [u, par], [Gs]),
                          ca.Function("J", [u, par], [ca.jacobian(Gs, u)]), nw, par.numel())
    # the solution, and the residual it leaves, as MX of p
    P = ca.MX.sym("p", p.numel())
    xg0 = ca.Function("guess", [p], [x_guess])(P)
    u0 = ca.Function("u0", [p], [w_guess / d])(P)
    iterates = loop(u0, ca.repmat(ca.vertcat(xg0, P), 1, MAX_ITER))
    sol = iterates[:, -1]
    resid = ca.Function("res", [u, xg, p], [ca.norm_inf(Gs)])(sol, xg0, P)
    wx = sol[:len(free)] * d[:len(free)] if free else ca.MX(0, 1)
    xs = ca.vertsplit(xg0, 1)
    for k, i in enumerate(free):
        xs[i] = wx[k]
    x = ca.densify(ca.vertcat(*xs))
    # x / 0 where the residual is too large (a NaN residual compares false
    # too): the start is then not finite, which ExitInitializationMode refuses
    out = x / ca.if_else(resid <= RESIDUAL_TOL, 1.0, 0.0)
    return ca.Function(name, [P], [out], ["p"], ["x0"])


ALPHAS = [0.5 ** k for k in range(12)]


def _damped_newton(G, J, nw, npar) -> ca.Function:
    """One damped Newton step u -> u + a du (du from the Jacobian, a the
    first of 1, 1/2, ... that lowers the residual), looped MAX_ITER times."""
    u, par = ca.MX.sym("u", nw), ca.MX.sym("par", npar)
    g = G(u, par)
    du = ca.solve(J(u, par), -g, "qr")
    n0 = ca.norm_2(g)
    nxt = u + ALPHAS[-1] * du
    for a in reversed(ALPHAS[:-1]):
        cand = u + a * du
        nxt = ca.if_else(ca.norm_2(G(cand, par)) <= (1 - 1e-4 * a) * n0, cand, nxt)
    step = ca.Function("pdbfs_start_step", [u, par], [nxt])
    return step.mapaccum("pdbfs_start_newton", MAX_ITER)
