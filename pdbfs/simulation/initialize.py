"""Initialization: the start of a rig as a nonlinear system, solved before
integration (Modelica's initialization problem).

Unknowns: the free states (``fixed=False``; with ``initial="steady"`` every
state; with ``initial=[names]`` those too) and, for rigs with algebraic
variables, z. Equations: the components' initial equations, ``der(x) = 0``
for the states chosen steady, and the algebraic equations. The fixed states
start at their start values. Newton's method with the exact Jacobian
(CasADi's automatic differentiation of the DAE), damped by a backtracking
line search on the scaled residual so that a guess outside a contact does
not send it away; the start values of the free states are its guess.

A system that is not square, singular at a Newton iterate, or whose residual
does not vanish is refused in one line naming its equations and unknowns.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError, ParameterError
from pdbfs.modelling.initialization import (check_initial, needs_solving, square_start,  # noqa: F401
                                            start_residual,
                                            start_system)

MAX_ITER = 100
STEP_TOL = 1e-13      # converged when every step is below this, relative to the unknown
RESIDUAL_TOL = 1e-8   # accepted when every residual is below this, relative to its terms
SINGULAR = 1e-13      # reciprocal condition number of the scaled Jacobian called singular


@dataclass
class InitialState:
    """The start a run began from: every state's value, what was solved,
    and how well (``residuals``: each equation's residual divided by the
    size of its terms)."""

    values: dict                       # state name -> start value
    solved: list = field(default_factory=list)      # unknowns solved for
    equations: list = field(default_factory=list)   # the equations that determined them
    residuals: dict = field(default_factory=dict)   # equation -> scaled residual
    iterations: int = 0

    def __getitem__(self, name):
        return self.values[name]

    def to_dict(self) -> dict:
        return {"values": dict(self.values), "solved": list(self.solved),
                "equations": list(self.equations), "iterations": self.iterations,
                "max_residual": max(self.residuals.values(), default=0.0)}


def refuse_solved_start(dae, what: str):
    """One line for the paths that start from the declared start values as a
    function of the parameters (and so cannot take a solved start yet)."""
    if needs_solving(dae, None):
        free = [n for n, f in zip(dae.x_names, dae.x_fixed or []) if not f]
        raise ParameterError(f"rig {dae.name}: its start is solved at initialization "
                             f"({', '.join(free) or 'initial equations'}), which {what} does "
                             "not do yet")


def solve_start(sim, p, x_guess, initial=None, t0=0.0):
    """(x0, InitialState): the start of a run, solved where the rig or
    ``initial`` asks (else x_guess as it is)."""
    dae = sim.dae
    x_guess = np.asarray(x_guess, float)
    if not needs_solving(dae, initial):
        return x_guess, InitialState(dict(zip(dae.x_names, x_guess.tolist())))
    free, eqs, eq_names = start_system(dae, initial)
    unknowns, eq_names = square_start(dae, free, eqs, eq_names)
    F = _functions(sim, tuple(free), initial)
    w = np.concatenate([x_guess[free], sim.z_guess(p)])
    args = (t0, x_guess, p)
    w, res, it = _newton(F, w, args, eq_names, unknowns, dae.name)
    x0 = x_guess.copy()
    x0[free] = w[:len(free)]
    if not np.all(np.isfinite(x0)):
        raise ModelError(f"the start of rig {dae.name} is not finite after initialization")
    return x0, InitialState(dict(zip(dae.x_names, x0.tolist())), unknowns, eq_names,
                            dict(zip(eq_names, res.tolist())), it)


def _functions(sim, free, initial):
    """G(w, t, x_guess, p) and its Jacobian in w, cached per system."""
    key = ("init", free, None if initial is None else tuple(initial))
    F = sim._cache.get(key)
    if F is None:
        dae = sim.dae
        _, eqs, _ = start_system(dae, initial)
        w, xg, G = start_residual(dae, list(free), eqs)
        F = ca.Function("init", [w, dae.t, xg, dae.p], [G, ca.jacobian(G, w)])
        sim._cache[key] = F
    return F


def _newton(F, w, args, eq_names, unknowns, rig):
    """Damped Newton on G(w) = 0; returns (w, scaled residuals, iterations)."""
    def evaluate(w):
        g, J = F(w, *args)
        return np.asarray(g, float).ravel(), np.asarray(J, float)

    d = np.maximum(np.abs(w), 1e-8)            # column scales: the unknowns' sizes
    g, J = evaluate(w)
    for it in range(1, MAX_ITER + 1):
        if not (np.all(np.isfinite(g)) and np.all(np.isfinite(J))):
            raise ModelError(f"the start of rig {rig}: the initial equations are not finite at "
                             f"the guess ({_worst(eq_names, ~np.isfinite(g))})")
        d = np.maximum(d, np.abs(w))
        r = np.abs(J) @ d                      # row scales: the size of each equation's terms
        r = np.where(r > 0, r, 1.0)
        Js = J * d / r[:, None]
        _check_regular(Js, eq_names, unknowns, rig)
        step = np.linalg.solve(Js, -g / r) * d
        norm0 = np.linalg.norm(g / r)
        alpha = 1.0
        while True:                            # backtracking on the scaled residual
            g_new, J_new = evaluate(w + alpha * step)
            if np.all(np.isfinite(g_new)) and \
                    np.linalg.norm(g_new / r) <= (1 - 1e-4 * alpha) * norm0 or alpha < 1e-6:
                break
            alpha *= 0.5
        w, g, J = w + alpha * step, g_new, J_new
        if np.all(np.abs(alpha * step) <= STEP_TOL * np.maximum(np.abs(w), d)) or \
                np.linalg.norm(g / r) == 0.0:
            break
    r = np.abs(J) @ np.maximum(d, np.abs(w))
    scaled = np.abs(g) / np.where(r > 0, r, 1.0)
    if not np.all(scaled <= RESIDUAL_TOL):
        raise ModelError(
            f"the start of rig {rig} has no solution Newton could find: "
            f"{_worst(eq_names, scaled > RESIDUAL_TOL)} stay(s) unsatisfied "
            f"(relative residual {np.max(scaled):.3g} after {it} iterations) for "
            f"{', '.join(unknowns)}")
    return w, scaled, it


def _check_regular(Js, eq_names, unknowns, rig):
    if Js.size == 0:
        return
    u, s, vt = np.linalg.svd(Js)
    if s[-1] > SINGULAR * s[0] and s[-1] > 0:
        return
    left, right = np.abs(u[:, -1]), np.abs(vt[-1])
    eqs = [n for n, a in zip(eq_names, left) if a > 0.1 * left.max()]
    xs = [n for n, a in zip(unknowns, right) if a > 0.1 * right.max()]
    raise ModelError(
        f"the start of rig {rig} is not determined: the initial system is singular in "
        f"{', '.join(eqs)}, which do(es) not fix {', '.join(xs)} (a body touching nothing, "
        "or an equation that does not depend on the free states?)")


def _worst(names, mask):
    return ", ".join(n for n, m in zip(names, mask) if m) or "none"
