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

import numpy as np

from .impulse import integral

#: relative interpolation error (of the signal's scale) accepted without checking
TRUST = 1e-8


class Curves:
    """The Hermite data of one Result (built lazily per variable)."""

    def __init__(self, res):
        self.res, self.t = res, res.t
        self._rows = {}
        self._kinks = None

    @property
    def kinks(self) -> np.ndarray:
        """Per output interval: True where an event indicator changes sign."""
        if self._kinks is None:
            E = self.res._sim.events_on(self.t, self.res._X, self.res._Z, self.res.p)
            s = np.sign(E)
            self._kinks = np.any(s[:, :-1] * s[:, 1:] <= 0, axis=0) if E.size else \
                np.zeros(len(self.t) - 1, dtype=bool)
        return self._kinks

    def data(self, name):
        """(y, dy/dt, trusted interval mask) of ``name``, or None without derivatives."""
        if name not in self._rows:
            sim = self.res._sim
            rate = sim.rates_on(self.t, self.res._X, self.res._Z, self.res.p, name)
            if rate is None:
                self._rows[name] = None
            else:
                y = self.res[name]
                c = coefficients(self.t, y, rate)
                h = np.diff(self.t)
                jerk = 6.0 * c[3] / h ** 3                   # y''' on each interval
                jump = np.abs(np.diff(jerk))
                err = np.zeros_like(h)
                err[:-1] = np.maximum(err[:-1], jump * h[:-1] ** 3 / 384)
                err[1:] = np.maximum(err[1:], jump * h[1:] ** 3 / 384)
                scale = max(float(np.max(np.abs(y))), 1e-300)
                trusted = (err <= TRUST * scale) & ~self.kinks
                self._rows[name] = (y, rate, c, trusted)
        return self._rows[name]

    def peak(self, name, k, sign=1.0):
        """(t, value) of the largest of sign * ``name`` on the intervals next to
        sample k, or None if either is not trusted."""
        d = self.data(name)
        if d is None:
            return None
        y, _, c, trusted = d
        best = (float(self.t[k]), float(y[k]))
        for i in (k - 1, k):
            if i < 0 or i >= len(self.t) - 1:
                continue
            if not trusted[i]:
                return None
            a, b, cc, dd = (sign * c[m][i] for m in range(4))
            for s in _quadratic_roots(3 * dd, 2 * cc, b):
                if 0.0 < s < 1.0:
                    v = a + s * (b + s * (cc + s * dd))
                    if v > sign * best[1]:
                        best = (float(self.t[i] + s * (self.t[i + 1] - self.t[i])), float(sign * v))
        return best

    def crossing(self, name, level, i):
        """The time ``name`` crosses ``level`` in interval i, or None if not trusted."""
        d = self.data(name)
        if d is None or not d[3][i]:
            return None
        c = [m[i] for m in d[2]]
        roots = np.roots([c[3], c[2], c[1], c[0] - level]) if any(c[1:]) else []
        real = sorted(r.real for r in np.atleast_1d(roots) if abs(r.imag) < 1e-9 and -1e-12 <= r.real <= 1 + 1e-12)
        if len(real) != 1:
            return None                                      # two turns in one step: not trusted
        return float(self.t[i] + min(max(real[0], 0.0), 1.0) * (self.t[i + 1] - self.t[i]))

    def integral(self, name, a, b):
        """The integral of ``name`` over [a, b] on the interpolant (None without derivatives)."""
        d = self.data(name)
        if d is None:
            return None
        return integral(self.t, d[0], a, b, d[1])


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
