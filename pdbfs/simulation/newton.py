"""Damped Newton on the start system G(w) = 0 (initialize.py), one run from
one guess, reported rather than raised: where it stopped, why, and the
scaled residual and Jacobian there, so that the start search
(start_branches.py) can try other guesses when a run stops at a singular
Jacobian (a one-sided law that does not act at the guess).

The unknowns are scaled by their sizes (``d``, the largest seen, at least
1e-8), the equations by the size of their terms (``r = |J| d``); the step
is damped by backtracking on the scaled residual so that a guess outside a
contact does not send it away.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAX_ITER = 100
STEP_TOL = 1e-13      # converged when every step is below this, relative to the unknown
RESIDUAL_TOL = 1e-8   # accepted when every residual is below this, relative to its terms
SINGULAR = 1e-13      # reciprocal condition number of the scaled Jacobian called singular


@dataclass
class Outcome:
    """Where one Newton run stopped: ``status`` "converged" (steps below
    STEP_TOL or a zero residual), "singular" (the scaled Jacobian at ``w``
    is singular and the residual that it does fix is satisfied),
    "nonfinite" (the equations are not finite at ``w``) or "stopped"
    (MAX_ITER iterations)."""

    w: np.ndarray
    g: np.ndarray         # residuals at w
    J: np.ndarray         # their Jacobian at w
    d: np.ndarray         # column scales (the unknowns' sizes)
    iterations: int
    status: str

    @property
    def scaled(self) -> np.ndarray:
        """Each residual divided by the size of its terms."""
        r = np.abs(self.J) @ np.maximum(self.d, np.abs(self.w))
        return np.abs(self.g) / np.where(r > 0, r, 1.0)

    @property
    def solved(self) -> bool:
        """Whether every scaled residual is below RESIDUAL_TOL (and finite)."""
        return self.status != "nonfinite" and bool(np.all(self.scaled <= RESIDUAL_TOL))

    def scaled_jacobian(self) -> tuple[np.ndarray, np.ndarray]:
        """(Js, r): the Jacobian in scaled unknowns and equations, and the row scales."""
        d = np.maximum(self.d, np.abs(self.w))
        r = np.abs(self.J) @ d
        r = np.where(r > 0, r, 1.0)
        return self.J * d / r[:, None], r

    def null_spaces(self):
        """(U, V): the left and right singular vectors of the scaled Jacobian
        whose singular values are below SINGULAR times the largest (empty
        when it is regular)."""
        Js, _ = self.scaled_jacobian()
        n = Js.shape[1]
        if Js.size == 0:
            return np.zeros((0, 0)), np.zeros((n, 0))
        u, s, vt = np.linalg.svd(Js)
        small = (s <= SINGULAR * s[0]) | (s == 0)
        return u[:, small], vt[small].T

    @property
    def regular(self) -> bool:
        """Whether the scaled Jacobian at ``w`` is not singular."""
        return self.null_spaces()[1].shape[1] == 0


def run(F, w, args) -> Outcome:
    """Damped Newton on G(w) = 0 from ``w``; F(w, *args) -> (G, dG/dw)."""
    def evaluate(w):
        g, J = F(w, *args)
        return np.asarray(g, float).ravel(), np.asarray(J, float).reshape(len(w), len(w))

    w = np.asarray(w, float)
    d = np.maximum(np.abs(w), 1e-8)
    g, J = evaluate(w)
    if w.size == 0:                            # nothing to solve for
        return Outcome(w, g, J, d, 0, "converged")
    it = 0
    while True:
        if not (np.all(np.isfinite(g)) and np.all(np.isfinite(J))):
            return Outcome(w, g, J, d, it, "nonfinite")
        d = np.maximum(d, np.abs(w))
        here = Outcome(w, g, J, d, it, "singular")
        Js, r = here.scaled_jacobian()
        u, s, vt = np.linalg.svd(Js)
        keep = (s > SINGULAR * s[0]) & (s > 0)
        if np.all(keep):
            if it == MAX_ITER:
                return Outcome(w, g, J, d, it, "stopped")
            step = np.linalg.solve(Js, -g / r) * d
            merit = lambda g: np.linalg.norm(g / r)          # noqa: E731
        else:
            # singular: least-squares steps satisfy what the Jacobian does fix
            # (a velocity at rest), then the run stops there (the start search
            # goes on from it)
            P = u[:, keep].T
            fixable = P @ (g / r)
            if it == MAX_ITER or np.linalg.norm(fixable) <= RESIDUAL_TOL:
                return here
            step = vt[keep].T @ (-fixable / s[keep]) * d
            merit = lambda g: np.linalg.norm(P @ (g / r))    # noqa: E731
        it += 1
        norm0 = merit(g)
        alpha = 1.0
        while True:                            # backtracking on the scaled residual
            g_new, J_new = evaluate(w + alpha * step)
            if np.all(np.isfinite(g_new)) and merit(g_new) <= (1 - 1e-4 * alpha) * norm0 \
                    or alpha < 1e-6:
                break
            alpha *= 0.5
        w, g, J = w + alpha * step, g_new, J_new
        if np.all(np.abs(alpha * step) <= STEP_TOL * np.maximum(np.abs(w), d)) or \
                np.linalg.norm(g / r) == 0.0:
            return Outcome(w, g, J, np.maximum(d, np.abs(w)), it, "converged")
