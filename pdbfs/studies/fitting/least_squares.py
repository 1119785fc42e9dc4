"""The least-squares engine: bounded, scaled, multistart, on exact Jacobians
(scipy's trust-region reflective ``least_squares``), and what the Jacobian
at the optimum says about the fit (standard errors, correlations, which
unknowns the data do not determine).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from pdbfs.errors import PdbfsError

#: a direction whose singular value is below this fraction of the largest is not determined
SINGULAR = 1e-6
#: an unknown is not determined when its standard error in scaled units exceeds this
#: (log-scaled: a factor e either way)
MAX_SCALED_STD = 1.0


@dataclass
class Start:
    """One start of a multistart fit and where it ended."""

    z0: np.ndarray
    z: np.ndarray | None = None
    cost: float = math.inf
    iterations: int = 0
    status: str = ""


@dataclass
class Fit:
    """The best of a least-squares fit's starts, and every start's outcome."""

    z: np.ndarray              # scaled unknowns at the optimum
    residual: np.ndarray
    jac: np.ndarray            # d residual / d z at the optimum
    cost: float                # 0.5 * sum(residual^2)
    starts: list[Start] = field(default_factory=list)
    active: list[int] = field(default_factory=list)   # indices of unknowns at a bound: -1 lower, +1 upper
    evaluations: int = 0


def solve(fun, z0, lo, hi, *, starts: int = 1, seed: int = 0, xtol=1e-10, ftol=1e-12,
          max_nfev: int = 200) -> Fit:
    """Minimise 0.5 |r(z)|^2 within [lo, hi]; ``fun(z)`` returns (r, dr/dz).
    The first start is ``z0``, further ones a Latin hypercube in the box."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    cache = {}

    def both(z):
        key = np.asarray(z, float).tobytes()
        if key not in cache:
            cache.clear()
            cache[key] = fun(np.asarray(z, float))
        return cache[key]

    # scipy's optimizers and statistics: imported by a fit, not by ``import pdbfs.studies``
    from scipy.optimize import least_squares
    from scipy.stats import qmc
    points = [np.clip(np.asarray(z0, float), lo, hi)]
    if starts > 1:
        sample = qmc.LatinHypercube(d=len(lo), seed=seed).random(starts - 1)
        points += list(qmc.scale(sample, lo, hi))
    runs, best, n_eval = [], None, 0
    for p in points:
        st = Start(z0=p)
        try:
            r = least_squares(lambda z: both(z)[0], p, jac=lambda z: both(z)[1], bounds=(lo, hi),
                              method="trf", x_scale=1.0, xtol=xtol, ftol=ftol, gtol=1e-12,
                              max_nfev=max_nfev)
            st.z, st.cost, st.iterations, st.status = r.x, float(r.cost), int(r.nfev), r.message
            n_eval += r.nfev + r.njev
            if best is None or r.cost < best.cost:
                best = r
        except PdbfsError as err:   # a start in a region where the rig cannot be simulated
            st.status = f"failed: {err}"
        runs.append(st)
    if best is None:
        raise PdbfsError("every start of the fit failed; the first: " + runs[0].status[8:])
    active = []
    for i, (z, a, b) in enumerate(zip(best.x, lo, hi)):
        tol = 1e-6 * max(1.0, b - a)
        active.append(-1 if z - a < tol else (1 if b - z < tol else 0))
    r, J = fun(best.x)
    return Fit(best.x, r, J, float(0.5 * r @ r), runs, active, n_eval)


def optimum_of_each_start(fit: Fit, rel: float = 1e-3, ztol: float = 1e-3) -> list:
    """For each start, which optimum it ended at (0: the best, 1: the next
    best, ...; None: the start failed). Two ends are one optimum when their
    scaled unknowns agree within ``ztol`` or their costs within ``rel`` (a
    perfect fit's costs are all near 0, and differ relatively by much)."""
    ends = sorted((s.cost, i) for i, s in enumerate(fit.starts) if s.z is not None)
    groups, which = [], [None] * len(fit.starts)   # groups: (cost, z) of each optimum
    for c, i in ends:
        z = np.asarray(fit.starts[i].z, float)
        for g, (c0, z0) in enumerate(groups):
            if np.max(np.abs(z - z0), initial=0.0) <= ztol or c <= c0 * (1 + rel) + 1e-300:
                which[i] = g
                break
        else:
            which[i] = len(groups)
            groups.append((c, z))
    return which


def distinct_optima(fit: Fit, rel: float = 1e-3) -> int:
    """How many different optima the starts found (optimum_of_each_start)."""
    return len({w for w in optimum_of_each_start(fit, rel) if w is not None})


@dataclass
class Statistics:
    """Standard errors and correlations of a fit, from the Jacobian at its optimum."""

    std_z: np.ndarray          # standard errors of the scaled unknowns (inf: not determined)
    cov_z: np.ndarray
    corr: np.ndarray
    sigma: float               # residual standard deviation (in residual units)
    singular: np.ndarray       # singular values of the Jacobian, largest first
    entangled: list            # index groups spanning near-singular directions, the
                               # unknown with the largest share first
    loose: list                # indices whose standard error exceeds MAX_SCALED_STD

    @property
    def undetermined(self) -> list[int]:
        """One unknown per near-singular direction (the others of its group
        are fitted once it is held), and every loose one."""
        return sorted({g[0] for g in self.entangled} | set(self.loose))


def statistics(residual, jac) -> Statistics:
    """Gauss-Newton statistics at an optimum: cov = s^2 (J^T J)^-1 with
    s^2 = RSS / (m - n). The unknowns that make up a near-singular direction
    of J (singular value below SINGULAR of the largest), and those with a
    standard error beyond MAX_SCALED_STD, are not determined by the data."""
    m, n = jac.shape
    sigma = math.sqrt(float(residual @ residual) / max(m - n, 1))
    _, s, Vt = np.linalg.svd(jac, full_matrices=False)
    small = s < SINGULAR * (s[0] if s.size and s[0] > 0 else 1.0)
    entangled = []
    for k in np.flatnonzero(small):
        v = np.abs(Vt[k])
        group = [int(i) for i in np.flatnonzero(v > 0.2 * v.max())]
        entangled.append(sorted(group, key=lambda i: -v[i]))
    inv_s2 = np.where(small, 0.0, 1.0 / np.where(small, 1.0, s) ** 2)
    cov = sigma ** 2 * (Vt.T * inv_s2) @ Vt
    std = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    in_groups = {i for g in entangled for i in g}
    loose = [i for i in range(n) if i not in in_groups and std[i] > MAX_SCALED_STD]
    std = np.where([i in in_groups or i in loose for i in range(n)], np.inf, std)
    d = np.sqrt(np.diag(cov))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(d, d)
    corr[~np.isfinite(corr)] = np.nan
    return Statistics(std, cov, corr, sigma, s, entangled, loose)
