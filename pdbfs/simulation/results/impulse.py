"""Impulses of a contact-force history and Guo & Batzer's restitution
estimate (paper eq. 8): the impulse after a split instant divided by the
impulse before it, for a body initially at rest.

For force histories given as samples (the paper's figures, the tests, the
Hermite curves of a Result): closed forms per interval (scipy's splines cost
0.1 ms a call). The summary's restitution does not sample: its impulses are
integrated by the solver (contact_impulse.py), as the C summary driver's
(c/pdbfs_summary.c), so that a blow shorter than the output step counts.
"""
from __future__ import annotations

import numpy as np


def integral(t, y, a, b, rate=None) -> float:
    """The integral of the sampled ``y`` over [a, b] (clipped to the samples;
    b < a gives minus the integral over [b, a]): exactly, on the cubic
    Hermite interpolant when the time derivatives ``rate`` are given (error
    O(h^4)), else on the piecewise-linear one (the trapezoidal rule).
    Closed forms per interval, a few numpy operations (no spline object)."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    a, b = min(max(a, t[0]), t[-1]), min(max(b, t[0]), t[-1])
    if b < a:
        return -integral(t, y, b, a, rate)
    if t.size < 2 or b == a:
        return 0.0
    m = None if rate is None else np.asarray(rate, float)
    ia, ib = (min(max(int(np.searchsorted(t, x, side="right")) - 1, 0), t.size - 2) for x in (a, b))
    h = t[ia + 1:ib + 1] - t[ia:ib]
    whole = 0.5 * h * (y[ia:ib] + y[ia + 1:ib + 1])      # the intervals from ia to ib - 1
    if m is not None:
        whole += h * h * (m[ia:ib] - m[ia + 1:ib + 1]) / 12.0
    return float(np.sum(whole)) + _part(t, y, m, ib, b) - _part(t, y, m, ia, a)


def _part(t, y, m, i, x) -> float:
    """The integral over [t[i], x] of interval i's interpolant."""
    h = t[i + 1] - t[i]
    s = (x - t[i]) / h
    y0, y1 = y[i], y[i + 1]
    if m is None:
        return float(h * s * (y0 + 0.5 * s * (y1 - y0)))
    m0, m1 = m[i] * h, m[i + 1] * h          # the cubic y0 + m0 s + c s^2 + d s^3
    c = 3.0 * (y1 - y0) - 2.0 * m0 - m1
    d = 2.0 * (y0 - y1) + m0 + m1
    return float(h * s * (y0 + s * (m0 / 2.0 + s * (c / 3.0 + s * d / 4.0))))


def impulse_ratio(t, force, t_split, t_end=None, rate=None) -> float | None:
    """Impulse of ``force`` over [t_split, t_end] divided by its impulse over
    [t[0], t_split] (``t_end`` defaults to the last sample); None where the
    ratio is not defined (no impulse before the split)."""
    t_end = float(t[-1]) if t_end is None else t_end
    before = integral(t, force, float(t[0]), t_split, rate)
    after = integral(t, force, t_split, t_end, rate)
    if not (np.isfinite(before) and np.isfinite(after)) or before <= 0:
        return None
    return after / before


def restitution_from_force(t, force, t_split=None) -> float | None:
    """Coefficient of restitution from a sampled contact-force history (Guo
    & Batzer): the impulse ratio of the first contact (the first run of
    positive force; the hammer may strike again), split at its force peak,
    or at ``t_split`` (e.g. the instant of maximum indentation, which turns
    the ratio into Poisson's restitution: with hysteresis damping the force
    peaks before maximum indentation, so the split at the peak gives a
    larger ratio). None where not defined (no positive force)."""
    t = np.asarray(t, float)
    f = np.asarray(force, float)
    if t.shape != f.shape or t.size < 3:
        raise ValueError("restitution_from_force: t and force must be equal-length arrays")
    on = np.flatnonzero(f > 0)
    if on.size == 0:
        return None
    start = max(on[0] - 1, 0)
    gaps = np.flatnonzero(f[on[0]:] <= 0)
    stop = on[0] + gaps[0] if gaps.size else f.size - 1
    tt, ff = t[start:stop + 1], np.clip(f[start:stop + 1], 0.0, None)
    split = float(tt[int(np.argmax(ff))]) if t_split is None else float(t_split)
    return impulse_ratio(tt, ff, split)
