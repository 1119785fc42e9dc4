"""Initialization: the start of a rig as a nonlinear system, solved before
integration (Modelica's initialization problem).

Unknowns: the free states (``fixed=False``; with ``initial="steady"`` every
state; with ``initial=[names]`` those too) and, for rigs with algebraic
variables, z. Equations: the components' initial equations, ``der(x) = 0``
for the states chosen steady, and the algebraic equations. The fixed states
start at their start values. Newton's method with the exact Jacobian
(CasADi's automatic differentiation of the DAE), damped by a backtracking
line search (newton.py); the start values of the free states are its
guess. Where the guess lies on the slack side of a one-sided law (a hammer
outside the contact it rests on, an oil column at zero compression), the
Jacobian is singular there: guesses across the laws' kinks are tried
(start_branches.py), and the start is the one solution found.

A system that is not square, has no solution, or more than one (a singular
one: a body free to move), is refused in one line naming its equations and
unknowns.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError, ParameterError
from pdbfs.modelling.initialization import (check_initial, needs_solving, on_unknowns,  # noqa: F401
                                            rate_hint, square_start, start_system)

from . import start_branches


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
        """The start as plain JSON-ready data, with the largest residual."""
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
    F, E = _functions(sim, tuple(free), initial)
    w = np.concatenate([x_guess[free], sim.z_guess(p)])
    args = (t0, x_guess, p)
    found = start_branches.search(F, E, w, args)
    sol = start_branches.decide(found, eq_names, unknowns, dae.name,
                                lambda eqs, xs: rate_hint(dae, eqs, unknowns))
    x0 = x_guess.copy()
    x0[free] = sol.w[:len(free)]
    if not np.all(np.isfinite(x0)):
        raise ModelError(f"the start of rig {dae.name} is not finite after initialization")
    return x0, InitialState(dict(zip(dae.x_names, x0.tolist())), unknowns, eq_names,
                            dict(zip(eq_names, sol.scaled.tolist())), sol.iterations)


def _functions(sim, free, initial):
    """(F, E): the residuals G(w, t, x_guess, p) and their Jacobian in w,
    and the event indicators and theirs, cached per system."""
    key = ("init", free, None if initial is None else tuple(initial))
    FE = sim._cache.get(key)
    if FE is None:
        dae = sim.dae
        _, eqs, _ = start_system(dae, initial)
        n = len(eqs) + dae.z.numel()
        w, xg, GE = on_unknowns(dae, list(free), ca.vertcat(*eqs, dae.alg, dae.events))
        G, Ev = GE[:n], GE[n:]
        args = [w, dae.t, xg, dae.p]
        FE = (ca.Function("init", args, [G, ca.jacobian(G, w)]),
              ca.Function("init_events", args, [Ev, ca.jacobian(Ev, w)]))
        sim._cache[key] = FE
    return FE
