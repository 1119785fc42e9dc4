"""The start of a rig across its one-sided laws: where Newton from the guess
stops at a singular Jacobian, try guesses on the other side of the laws'
kinks, and decide from every solution found.

A contact, an oil column or a compression-only spring acts on one side of
its kink only (its event indicator, Component.events(), changes sign
there). A guess on the slack side (a hammer outside the contact it rests
on, an oil column exactly at zero compression) gives a Jacobian that does
not depend on the positions the law would fix, so Newton cannot start.
Then, for each event indicator that moves along the Jacobian's null space,
the guess is moved within that null space (the other equations stay as
they were, to first order) to the other side of the kink, and Newton runs
again from there; so on from where those runs stop, up to MAX_RUNS runs.

Every start found is a solution of the same equations. One (to
SAME_SOLUTION, relative) is the start; several are a start that is not
determined (a body free to move: a continuum of starts); none is a start
without solution.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pdbfs.errors import ModelError

from . import newton

MAX_RUNS = 48
SAME_SOLUTION = 1e-6     # two solutions are one when every unknown agrees to this, relative
MARGIN = 1e-3            # how far past a kink a guess is placed, relative to the unknowns


@dataclass
class Search:
    """Everything the search ran: the first run (from the guess), every
    solution found."""

    first: newton.Outcome
    solutions: list = field(default_factory=list)    # solved Outcomes

    def distinct(self) -> list:
        """The solutions, one per distinct start (regular ones first)."""
        out = []
        for o in sorted(self.solutions, key=lambda o: (not o.regular, np.max(o.scaled,
                                                                                initial=0.0))):
            if not any(_same(o, k) for k in out):
                out.append(o)
        return out


def search(F, E, w0, args) -> Search:
    """Newton from ``w0``; where it stops at a singular Jacobian (or at a
    solution where it is singular), guesses across the event indicators
    E(w, *args) -> (e, de/dw). Returns the Search (decide() reads it)."""
    first = newton.run(F, w0, args)
    found = Search(first)
    if first.solved and first.regular:
        found.solutions.append(first)
        return found
    if first.status == "nonfinite":
        return found
    queue, runs, probed, rested = [first], 1, set(), []
    while queue and runs < MAX_RUNS:
        o = queue.pop(0)
        guesses = []
        if o.solved:
            found.solutions.append(o)
            if len(found.distinct()) > 1:
                break                       # more than one: decided
            if o.regular:
                continue
            if not any(_same(o, r) for r in rested):
                rested.append(o)            # a solution where the Jacobian is singular:
                guesses += _along(o)        # is it one of many (a body free to move)?
        elif o.status == "nonfinite" or o.regular:
            continue            # stuck or not finite: nothing to cross from
        e, De = (np.asarray(a, float) for a in E(o.w, *args))
        e = e.ravel()
        De = De.reshape(len(e), len(o.w))
        pattern = tuple(np.sign(e).tolist())
        if pattern not in probed:
            probed.add(pattern)
            guesses += _guesses(o, e, De)
        for _, w in guesses:
            if runs >= MAX_RUNS:
                break
            runs += 1
            queue.append(newton.run(F, w, args))
    return found


def _along(o):
    """(None, guess) pairs: the solution ``o`` moved a little along each
    direction its Jacobian does not fix, both ways: where those are
    solutions too, the start is not determined."""
    _, V = o.null_spaces()
    d = np.maximum(o.d, np.abs(o.w))
    return [(None, o.w + sign * MARGIN * v * d) for v in V.T for sign in (1.0, -1.0)]


def _guesses(o, e, De):
    """(indicator, guess) pairs: ``o.w`` moved within the null space of the
    scaled Jacobian until indicator k is on the other side of its kink (its
    mirror image, and just past the kink), or both sides when it is at it."""
    _, V = o.null_spaces()
    if V.shape[1] == 0:
        return []
    d = np.maximum(o.d, np.abs(o.w))
    out = []
    for k in range(len(e)):
        a = De[k] * d                       # de/du in the scaled unknowns u = w / d
        b = V.T @ a
        if not np.all(np.isfinite(a)) or np.linalg.norm(b) <= 1e-6 * np.linalg.norm(a):
            continue                        # does not move along the null space
        margin = MARGIN * np.linalg.norm(a)
        if abs(e[k]) > margin:
            targets = [-e[k], -np.sign(e[k]) * margin]
        else:
            targets = [margin, -margin]
        for target in targets:
            du = V @ b * (target - e[k]) / (b @ b)
            out.append((k, o.w + du * d))
    return out


def _same(a, b) -> bool:
    scale = np.maximum.reduce([np.abs(a.w), np.abs(b.w), a.d, b.d])
    return bool(np.all(np.abs(a.w - b.w) <= SAME_SOLUTION * scale))


def decide(found: Search, eq_names, unknowns, rig, hint=lambda eqs, xs: ""):
    """The one start found, or a ModelError (one short line) saying that
    there is none or more than one, naming the equations and unknowns
    concerned (the first of long lists); ``hint(eqs, xs)`` (lists of names)
    adds what to do."""
    sols = found.distinct()
    if len(sols) == 1:
        return sols[0]
    first = found.first
    if first.status == "nonfinite":
        raise ModelError(f"the start of rig {rig}: the initial equations are not finite at "
                         f"the guess ({_names(eq_names, ~np.isfinite(first.g))})")
    if len(sols) > 1:
        a, b = sols[0], sols[1]
        scale = np.maximum.reduce([np.abs(a.w), np.abs(b.w), a.d, b.d])
        differ = np.abs(a.w - b.w) > SAME_SOLUTION * scale
        k = int(np.argmax(np.abs(a.w - b.w) / scale))
        where = next((o for o in sols if not o.regular), None)
        if where is not None:
            eqs, xs = _support(where, eq_names, unknowns)
            what = f"{_join(eqs, 1)} {_verb(eqs, 'leaves', 'leave')} {_join(xs)} free"
        else:
            eqs, xs = [], _pick(unknowns, differ)
            what = f"its equations have more than one solution in {_join(xs)}"
        which = "" if xs == [unknowns[k]] else f"{unknowns[k]} = "
        raise ModelError(f"the start of rig {rig} is not determined: {what} ({which}"
                         f"{_pair(a.w[k], b.w[k])}){hint(eqs, xs)}")
    if first.status == "singular":
        eqs, xs = _support(first, eq_names, unknowns)
        U, _ = first.null_spaces()
        _, r = first.scaled_jacobian()
        left = np.abs(U.T @ (first.g / r))
        if left.size and np.max(left) > newton.RESIDUAL_TOL:
            raise ModelError(
                f"the start of rig {rig} has no solution: {_join(eqs)} "
                f"{_verb(eqs, 'stays', 'stay')} unsatisfied whatever {_join(xs)} (relative "
                f"residual {np.max(left):.3g}){hint(eqs, xs)}")
        raise ModelError(
            f"the start of rig {rig} is not determined: its equations are singular in "
            f"{_join(eqs)}, which {_verb(eqs, 'leaves', 'leave')} {_join(xs)} free{hint(eqs, xs)}")
    scaled = first.scaled
    bad = _pick(eq_names, scaled > newton.RESIDUAL_TOL)
    raise ModelError(
        f"the start of rig {rig} has no solution Newton could find: {_join(bad)} "
        f"{_verb(bad, 'stays', 'stay')} unsatisfied (relative residual {np.max(scaled):.3g} "
        f"after {first.iterations} iterations) for {_join(list(unknowns))}")


def _support(o, eq_names, unknowns):
    """(equations, unknowns) that the null spaces of ``o``'s Jacobian involve."""
    U, V = (np.abs(M) for M in o.null_spaces())
    return (_pick(eq_names, np.any(U > 0.1 * U.max(axis=0), axis=1)),
            _pick(unknowns, np.any(V > 0.1 * V.max(axis=0), axis=1)))


def _pick(names, mask) -> list:
    return [n for n, m in zip(names, mask) if m]


def _join(names, most=2) -> str:
    """Names joined, or the first of a list longer than ``most`` and how many more."""
    if len(names) > most:
        return f"{names[0]} and {len(names) - 1} more"
    return ", ".join(names) or "none"


def _pair(a: float, b: float) -> str:
    """``a or b`` with the digits that tell them apart."""
    rel = abs(a - b) / max(abs(a), abs(b), 1e-300)
    digits = min(9, max(3, 1 - int(np.floor(np.log10(rel))) if rel > 0 else 9))
    return f"{a:.{digits}g} or {b:.{digits}g}"


def _verb(names, one: str, many: str) -> str:
    return one if len(names) == 1 else many


def _names(names, mask) -> str:
    return _join(_pick(names, mask))
