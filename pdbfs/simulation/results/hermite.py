"""Peaks, level crossings and integrals of a Result's variables, located on
the cubic Hermite interpolant of the output grid: values and exact time
derivatives (dy/dt = (dy/dx) der(x) + dy/dt, from the DAE) at every output
point.

Between two output points the interpolant's error is about
h^3 |jump of y'''| / 384; where that estimate is below ``TRUST`` of the
signal's scale and no event indicator changes sign (no kink inside), the
interpolant is used as it is. Elsewhere (coarse grids, kinks, DAE rigs whose
derivatives are not at hand) the caller falls back to root finding on the
solution itself. Either way the answers do not depend on the output grid;
this way they cost a few numpy operations instead of tens of integrations.
"""
from __future__ import annotations

import weakref

import numpy as np

from .impulse import integral

#: relative interpolation error (of the signal's scale) accepted without checking
TRUST = 1e-8


class Curves:
    """The Hermite data of one Result (built lazily per variable)."""

    def __init__(self, res):
        # the Result by a weak reference (it holds these curves: no cycle for
        # the garbage collector to find after every run), its arrays directly
        self._res = weakref.ref(res)
        self._sim, self.t, self._X, self._Z, self._p = res._sim, res.t, res._X, res._Z, res.p
        self._rows = {}
        self._rates = {}      # d/dt of outputs, where computed beforehand (Result.prefetch)
        self._kinks = None

    def _row(self, name):
        res = self._res()
        if res is not None:
            return res[name]
        return self._sim.outputs(self.t, self._X, self._Z, self._p,
                                 [self._sim.dae.y_names.index(name)])[0]

    @property
    def kinks(self) -> np.ndarray:
        """Per output interval: True where an event indicator changes sign."""
        if self._kinks is None:
            self.set_events(self._sim.events_on(self.t, self._X, self._Z, self._p))
        return self._kinks

    def set_events(self, E):
        """The kinks from the event indicators ``E`` on the grid (one row each)."""
        s = np.sign(E)
        self._kinks = np.any(s[:, :-1] * s[:, 1:] <= 0, axis=0) if E.size else \
            np.zeros(len(self.t) - 1, dtype=bool)

    def data(self, name):
        """(y, dy/dt, scale = max |y|) of ``name``, or None without derivatives."""
        if name not in self._rows:
            rate = self._rates.pop(name, None)
            if rate is None:
                rate = self._sim.rates_on(self.t, self._X, self._Z, self._p, name)
            if rate is None:
                self._rows[name] = None
            else:
                y = self._row(name)
                self._rows[name] = (y, rate, max(float(np.max(np.abs(y))), 1e-300))
        return self._rows[name]

    def interval(self, name, i):
        """(the cubic's coefficients (a, b, c, d) in s = (t - t_i) / h on
        interval i, trusted or not), or None without derivatives. Trusted: its
        error estimate h^3 |jump of the third derivative| / 384 (the jumps at
        both ends) within TRUST of the signal's scale, and no kink inside.
        Worked out for the intervals asked only (a summary asks a few dozen
        of thousands)."""
        d = self.data(name)
        if d is None:
            return None
        y, rate, scale = d
        t = self.t
        coef = lambda j: _cubic(t[j + 1] - t[j], y[j], y[j + 1], rate[j], rate[j + 1])  # noqa: E731
        c = coef(i)
        h = t[i + 1] - t[i]
        jerk = 6.0 * c[3] / h ** 3                           # the third derivative on it
        limit = TRUST * scale
        trusted = not self.kinks[i]
        for j in (i - 1, i + 1):                             # the jumps at its ends
            if trusted and 0 <= j < len(t) - 1:
                hj = t[j + 1] - t[j]
                jump = abs(6.0 * coef(j)[3] / hj ** 3 - jerk)
                trusted = bool(jump * h ** 3 / 384 <= limit)
        return c, trusted

    def peak(self, name, k, sign=1.0, first=0, last=None):
        """(t, value) of the largest of sign * ``name`` on the intervals next to
        sample k that lie between samples ``first`` and ``last`` (a window's
        ends; default the grid's), or None if one of them is not trusted."""
        d = self.data(name)
        if d is None:
            return None
        y = d[0]
        last = len(self.t) - 1 if last is None else min(last, len(self.t) - 1)
        best = (float(self.t[k]), float(y[k]))
        for i in (k - 1, k):
            if i < max(first, 0) or i >= last:
                continue
            c, trusted = self.interval(name, i)
            if not trusted:
                return None
            a, b, cc, dd = (sign * c[m] for m in range(4))
            for s in _quadratic_roots(3 * dd, 2 * cc, b):
                if 0.0 < s < 1.0:
                    v = a + s * (b + s * (cc + s * dd))
                    if v > sign * best[1]:
                        best = (float(self.t[i] + s * (self.t[i + 1] - self.t[i])), float(sign * v))
        return best

    def crossing(self, name, level, i):
        """The time ``name`` crosses ``level`` in interval i, or None if not trusted."""
        got = self.interval(name, i)
        if got is None or not got[1]:
            return None
        c = [float(m) for m in got[0]]
        s = _one_root(c[0] - level, c[1], c[2], c[3])
        if s is None:
            return None                                      # two turns in one step: not trusted
        return float(self.t[i] + s * (self.t[i + 1] - self.t[i]))

    def integral(self, name, a, b):
        """The integral of ``name`` over [a, b] on the interpolant (None without derivatives)."""
        d = self.data(name)
        if d is None:
            return None
        return integral(self.t, d[0], a, b, d[1])


def _cubic(h, y0, y1, r0, r1):
    """One interval's cubic, by the operations of coefficients()."""
    m0, m1 = r0 * h, r1 * h
    return (y0, m0, 3.0 * (y1 - y0) - 2.0 * m0 - m1, 2.0 * (y0 - y1) + m0 + m1)


def coefficients(t, y, rate):
    """Per interval, the Hermite cubic a + b s + c s^2 + d s^3 in s = (t - t_k) / h
    through the values and slopes at both ends (written out: scipy's
    CubicHermiteSpline gives the same, at many times the cost on short rows)."""
    h = np.diff(t)
    y0, y1 = y[:-1], y[1:]
    m0, m1 = rate[:-1] * h, rate[1:] * h
    return (y0, m0, 3.0 * (y1 - y0) - 2.0 * m0 - m1, 2.0 * (y0 - y1) + m0 + m1)


def _quadratic_roots(A, B, C):
    if abs(A) < 1e-300:
        return [-C / B] if abs(B) > 1e-300 else []
    disc = B * B - 4 * A * C
    if disc < 0:
        return []
    q = -0.5 * (B + np.copysign(np.sqrt(disc), B))
    return [q / A] + ([C / q] if q != 0 else [])


def _one_root(c0, c1, c2, c3):
    """The root in [0, 1] of c0 + c1 s + c2 s^2 + c3 s^3 if it has exactly
    one there (a crossing), else None (none, several, or one where the cubic
    turns: not a clean crossing). Between the cubic's turning points it is
    monotone: a sign change there is bracketed and refined by Newton's
    method kept inside its bracket (no eigenvalues, no LAPACK)."""
    poly = lambda s: c0 + s * (c1 + s * (c2 + s * c3))       # noqa: E731
    slope = lambda s: c1 + s * (2.0 * c2 + s * 3.0 * c3)     # noqa: E731
    size = abs(c0) + abs(c1) + abs(c2) + abs(c3)
    if size == 0.0:
        return None
    cuts = [0.0] + sorted(r for r in _quadratic_roots(3.0 * c3, 2.0 * c2, c1) if 0.0 < r < 1.0) \
        + [1.0]
    found = []
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        f_lo, f_hi = poly(lo), poly(hi)
        if lo > 0.0 and abs(f_lo) <= 1e-13 * size:
            return None                                      # a root where it turns
        if f_lo == 0.0:
            found.append(lo)
            continue
        if f_lo * f_hi > 0:
            continue
        if f_hi == 0.0:
            if hi == 1.0:
                found.append(hi)
            continue
        s = lo - f_lo * (hi - lo) / (f_hi - f_lo)            # regula falsi start
        for _ in range(60):
            f = poly(s)
            if f == 0.0:
                break
            if (f < 0) == (f_lo < 0):
                lo, f_lo = s, f
            else:
                hi = s
            d = slope(s)
            step = s - f / d if d != 0.0 else 0.5 * (lo + hi)
            nxt = step if lo < step < hi else 0.5 * (lo + hi)
            if abs(nxt - s) <= 4e-16 * max(1.0, abs(s)):
                s = nxt
                break
            s = nxt
        found.append(s)
    found = sorted(set(found))
    return found[0] if len(found) == 1 else None
