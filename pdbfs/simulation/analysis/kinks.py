"""One-sided laws exactly at their kink at a linearization's operating
point (linearize.py).

A contact, an oil column or a compression-only spring is not differentiable
where it engages (its event indicator, Component.events(), is zero there):
the Jacobian at that point is the one of the branch the law's equations
pick there, usually the slack one. Both one-sided answers are correct, but
they differ (the paper rig at its start: the oil column at zero compression
adds no stiffness, a hair later it adds k2). Each such law is named with the
side taken and whether the other side's linearization differs, found by
evaluating the Jacobian just past the kink on both sides, at two distances
(a law whose slope is continuous there, as Hertz's d^1.5, tends to the
same Jacobian on both sides as the distance shrinks; a kink keeps its jump).

A law at its kink in an input of the linearization (a valve commanded
exactly to its closed stop) is not differentiable in that input: the
derivative there is the mean of the two sides' (half the valve's gain).
Its columns of B and D are taken one-sided (``input_sides``): on the side
where the input acts, when on the other it does nothing (a stop); where
both sides act, differently, no side is right and the linearization is
refused, naming the law and the input.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError

AT_KINK = 1e-12      # an indicator is at its kink below this, relative to its terms
STEP = 1e-9          # how far past the kink the sides are looked at, relative to the states
SAME = 1e-9          # Jacobians agree to this, relative to their size
MAX_ENUMERATED = 6   # laws at their kinks whose sides are tried in every combination


@dataclass(frozen=True)
class Kink:
    """A one-sided law at its kink at the operating point: ``law`` is the
    event indicator's name (``oil.compression``), ``description`` what its
    sign change marks; the linearization is the one of the side where the
    indicator is ``side`` ("< 0" or "> 0"; None when both sides give the
    same, or neither); ``branch`` is "unloaded" or "loaded" where one
    side's Jacobian has the law's terms and the other not, "neither" where
    the Jacobian at the kink is neither side's (a slope between them), else
    None; ``differs`` whether the two sides linearize otherwise."""

    law: str
    description: str
    value: float
    side: str | None
    branch: str | None
    differs: bool
    #: the input of the linearization the law is at its kink in (its columns of B and
    #: D are the side ``side``'s), None for a kink in the states
    input: str | None = None

    def __str__(self) -> str:
        head = f"{self.law} = {self.value:g} ({self.description})" if self.description else \
            f"{self.law} = {self.value:g}"
        if self.input is not None:
            return (f"{head}: B and D in {self.input} taken on the side where it acts "
                    f"({self.law} {self.side}); on the other it does nothing")
        if not self.differs:
            return f"{head}: both sides linearize alike"
        if self.branch == "neither":
            return (f"{head}: its two sides linearize differently, and the linearization here is "
                    "neither side's (a slope between theirs)")
        taken = f"its {self.branch} side" if self.branch else "the side"
        other = {"unloaded": "loaded", "loaded": "unloaded"}.get(self.branch, "other")
        return (f"{head}: linearized on {taken} ({self.law} {self.side}); "
                f"its {other} side differs")

    def to_dict(self) -> dict:
        """The kink as plain JSON-ready data."""
        return {"law": self.law, "description": self.description, "value": self.value,
                "side": self.side, "branch": self.branch, "differs": self.differs,
                "input": self.input}


def kinks_at(sim, t, x, z, p) -> list:
    """The Kinks of the rig's one-sided laws at (t, x, z, p)."""
    dae = sim.dae
    F = _functions(sim)
    e, ex, ez = (np.asarray(a, float) for a in F["events"](t, x, z, p))
    e = e.ravel()
    if dae.z.numel():
        gx, gz = (np.asarray(a, float) for a in F["g"](t, x, z, p))
        ex = ex - ez @ np.linalg.solve(gz, gx)      # through the algebraic variables
    n_time = dae.time_events.numel()
    at = []
    for k in range(n_time, len(e)):
        terms = np.abs(ex[k]) @ np.abs(x) + (np.abs(ez[k]) @ np.abs(z) if len(z) else 0.0)
        if np.any(ex[k]) and abs(e[k]) <= AT_KINK * terms:
            at.append(k)
    if not at:
        return []
    J0 = _jacobian(sim, F, t, x, z, p)
    moves = _moves(ex[at], x)
    memo = {}

    def matches(signs):
        """Whether J0 is the Jacobian of the laws on the sides ``signs``
        (and that Jacobian just past them there)."""
        if signs not in memo:
            far, near = (_jacobian(sim, F, t, x + f * moves @ np.array(signs), None, p)
                         for f in (1.0, 1e-2))
            jump = np.linalg.norm(near - J0) > max(SAME * np.linalg.norm(J0),
                                                  0.5 * np.linalg.norm(far - J0))
            memo[signs] = (not jump, near)
        return memo[signs][0]

    ref = _reference(len(at), matches)
    out = []
    for i, k in enumerate(at):
        name = dae.event_names[k]
        text = dae.event_text.get(name, "")
        value = float(e[k]) + 0.0
        if ref is None:              # no sides reproduce J0 (a slope between the two)
            lo, hi = (((-1.0,) * i + (sign,) + (-1.0,) * (len(at) - i - 1)) for sign in (-1, 1))
            matches(lo), matches(hi)
            alike = np.linalg.norm(memo[lo][1] - memo[hi][1]) <= SAME * np.linalg.norm(J0)
            out.append(Kink(name, text, value, None, None if alike else "neither", not alike))
            continue
        flipped = ref[:i] + (-ref[i],) + ref[i + 1:]
        if matches(flipped):
            out.append(Kink(name, text, value, None, None, False))
            continue
        other = memo[flipped][1]
        nnz_here, nnz_other = np.count_nonzero(J0), np.count_nonzero(other)
        branch = None if nnz_here == nnz_other else \
            ("unloaded" if nnz_here < nnz_other else "loaded")
        out.append(Kink(name, text, value, "< 0" if ref[i] < 0 else "> 0", branch, True))
    return out


def _reference(m, matches):
    """Signs of the m indicators at their kinks whose sides give the
    Jacobian at the point: every combination for a few, else one sign at a
    time from all negative; None if none does."""
    if m <= MAX_ENUMERATED:
        return next((c for c in itertools.product((-1.0, 1.0), repeat=m) if matches(c)), None)
    c = (-1.0,) * m
    for i in range(m):
        if matches(c):
            return c
        c = c[:i] + (1.0,) + c[i + 1:]
        if not matches(c):
            c = c[:i] + (-1.0,) + c[i + 1:]
    return c if matches(c) else None


def _moves(ex, x):
    """Columns: moves of the states that put each indicator at its kink
    STEP past it (of the states it depends on, or 1e-6 of their units where
    those are all zero), the others unchanged (minimum-norm, to first
    order); a combination of signs times them puts each on its side."""
    size = np.array([max(np.max(np.abs(x[row != 0]), initial=0.0), 1e-6) for row in ex])
    targets = np.diag(STEP * size * np.linalg.norm(ex, axis=1))
    return np.linalg.lstsq(ex, targets, rcond=None)[0]


def _jacobian(sim, F, t, x, z, p):
    """d[ode; alg]/d[x; z] at (t, x, z), z solved for x when None."""
    if z is None:
        z = sim.consistent_start(t, x, p)[0] if not sim.dae.is_ode else np.zeros(0)
    return np.asarray(F["J"](t, x, z, p), float)


def _functions(sim):
    F = sim._cache.get("kinks")
    if F is None:
        dae = sim.dae
        args = [dae.t, dae.x, dae.z, dae.p]
        w = ca.vertcat(dae.x, dae.z)
        F = {"events": ca.Function("kink_events", args, [dae.events, ca.jacobian(dae.events, dae.x),
                                                        ca.jacobian(dae.events, dae.z)]),
             "g": ca.Function("kink_g", args, [ca.jacobian(dae.alg, dae.x),
                                              ca.jacobian(dae.alg, dae.z)]),
             "J": ca.Function("kink_J", args, [ca.jacobian(ca.vertcat(dae.ode, dae.alg), w)])}
        sim._cache["kinks"] = F
    return F


def input_sides(sim, t, x, p, inputs, cols, matrices):
    """(B, D columns replaced, Kinks) for the laws at their kink in one of
    ``inputs`` (names; ``cols`` their rows of p) at (t, x, p): each such
    column one-sided, on the side where the input acts (the other gives
    zero columns); ParameterError where both sides act differently.
    ``matrices(p)`` gives (B, D) at the parameters p (z solved again)."""
    dae = sim.dae
    if not cols or not dae.events.numel():
        return None, []
    F = sim._cache.get(("kinks_in", tuple(cols)))
    if F is None:
        u = ca.vertcat(*[dae.p[i] for i in cols])
        F = sim._cache[("kinks_in", tuple(cols))] = ca.Function(
            "kink_inputs", [dae.t, dae.x, dae.z, dae.p], [dae.events, ca.jacobian(dae.events, u)])
    z = sim.consistent_start(t, x, p)[0] if not dae.is_ode else np.zeros(0)
    e, eu = (np.asarray(a, float) for a in F(t, x, z, p))
    e = e.ravel()
    n_time = dae.time_events.numel()
    B = D = None
    out = []
    for j, (name, row) in enumerate(zip(inputs, cols)):
        at = [k for k in range(n_time, len(e)) if eu[k, j] != 0
              and abs(e[k]) <= AT_KINK * abs(eu[k, j]) * max(abs(p[row]), 1.0)]
        if not at:
            continue
        h = STEP * max(abs(p[row]), 1e-6 if abs(p[row]) == 0 else abs(p[row]))
        sides = []
        for sign in (1.0, -1.0):
            q = np.array(p, float)
            q[row] += sign * h
            Bs, Ds = matrices(q)
            sides.append(np.concatenate([Bs[:, j], Ds[:, j]]))
        size = max(np.linalg.norm(sides[0]), np.linalg.norm(sides[1]))
        if np.linalg.norm(sides[0] - sides[1]) <= SAME * max(size, 1e-300):
            continue                           # the two sides alike: not a kink in this input
        quiet = [np.linalg.norm(s) <= SAME * size for s in sides]
        k = at[0]
        law = dae.event_names[k]
        if quiet[0] == quiet[1]:
            raise ParameterError(
                f"linearize: {law} ({dae.event_text.get(law, 'a one-sided law')}) is at its kink "
                f"in input {name} here, and B and D differ on its two sides (largest "
                f"{_largest(sides[0]):.4g} above, {_largest(sides[1]):.4g} below): linearize "
                f"off the kink (another operating point or start value of {name})")
        acts = 0 if not quiet[0] else 1
        if B is None:
            B0, D0 = matrices(np.array(p, float))
            B, D = B0.copy(), D0.copy()
        nb = B.shape[0]
        B[:, j], D[:, j] = sides[acts][:nb], sides[acts][nb:]
        sign = (1.0 if acts == 0 else -1.0) * np.sign(eu[k, j])
        out.append(Kink(law, dae.event_text.get(law, ""), float(e[k]) + 0.0,
                        "> 0" if sign > 0 else "< 0", "loaded", True, name))
    return (None if B is None else (B, D)), out


def _largest(v) -> float:
    return float(v[np.argmax(np.abs(v))]) if v.size else 0.0
