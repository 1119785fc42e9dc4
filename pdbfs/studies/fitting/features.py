"""Features of a pulse and their exact parameter gradients: peak value, time
of peak, and the time spent above a fraction of the peak (the summary's
pulse duration, pdbfs.simulation.results.summary.PULSE_LEVEL).

From Samples (values, slopes and sensitivities on a fine grid) the features
are located on the Hermite interpolant and differentiated exactly:
the peak is stationary in t, so d(peak)/dp = dy/dp at the peak time; the
time of peak moves by -(d ydot/dp) / (d2y/dt2); a level crossing t_c of
the level L = base + PULSE_LEVEL * (peak - base) (base: the start pressure)
moves by -(dy/dp - dL/dp) / ydot(t_c).
"""
from __future__ import annotations

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.simulation.results.summary import PULSE_LEVEL

FEATURES = ("peak_pressure", "time_of_peak", "pulse_duration")
UNITS = {"peak_pressure": "Pa", "time_of_peak": "s", "pulse_duration": "s"}


def _refine_peak(s, k):
    """Time of the interpolant's maximum next to sample k (where its slope is 0)."""
    from scipy.optimize import brentq
    t = s.t
    slope = lambda tt: float(s.spline(tt, 1)[0])   # noqa: E731
    for a, b in ((t[max(k - 1, 0)], t[k]), (t[k], t[min(k + 1, len(t) - 1)])):
        if b > a and slope(a) > 0 > slope(b):
            return float(brentq(slope, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps))
    return float(t[k])


def pulse_features(s, want=FEATURES) -> tuple[dict, dict]:
    """({feature: value}, {feature: gradient over the parameters}) of Samples
    ``s``, for the features in ``want`` (the peak always)."""
    k = int(np.argmax(s.y))
    if k == len(s.y) - 1:
        raise PdbfsError(f"the pulse is still rising at t = {s.t[-1]:.6g} s: its peak is not "
                         "reached inside the horizon; raise t_end")
    t_pk = _refine_peak(s, k)
    y_pk, _, dy_pk = (a[0] for a in s.at([t_pk]))
    _, dydot_pk, yddot_pk = (a[0] for a in s.slope_at([t_pk]))
    values = {"peak_pressure": float(y_pk), "time_of_peak": t_pk}
    grads = {"peak_pressure": dy_pk,
             "time_of_peak": -dydot_pk / yddot_pk if yddot_pk < 0 else np.zeros_like(dy_pk)}
    if "pulse_duration" not in want:
        return values, grads
    # the level rises from the start (static) pressure, as the summary's (summary_run.py)
    base, _, dbase = (a[0] for a in s.at([s.t[0]]))
    level = base + PULSE_LEVEL * (y_pk - base)
    dlevel = dbase + PULSE_LEVEL * (dy_pk - dbase)
    crossings = _crossings(s, level)
    times, signs = [], []
    if s.y[0] > level:
        times.append(s.t[0])
        signs.append(0.0)          # the run's start does not move
    times += crossings
    signs += [1.0] * len(crossings)
    if s.y[-1] > level:
        raise PdbfsError(f"the pulse has not fallen below {PULSE_LEVEL:.0%} of its peak by "
                         f"t = {s.t[-1]:.6g} s: its duration is not defined; raise t_end")
    times, signs = np.asarray(times), np.asarray(signs)
    duration, grad = 0.0, np.zeros_like(dy_pk)
    if times.size:
        y_c, ydot_c, dy_c = s.at(times)
        moves = -(dy_c - dlevel) / np.where(ydot_c != 0, ydot_c, np.inf)[:, None]
        moves *= signs[:, None]
        duration = float(np.sum(times[1::2] - times[0::2]))
        grad = moves[1::2].sum(axis=0) - moves[0::2].sum(axis=0)
    values["pulse_duration"] = duration
    grads["pulse_duration"] = grad
    return values, grads


def _crossings(s, level) -> list[float]:
    """Times where y crosses ``level``, in order, located on the interpolant."""
    from scipy.optimize import brentq
    y = s.y - level
    idx = np.flatnonzero((np.sign(y[:-1]) * np.sign(y[1:]) < 0) | ((y[1:] == 0) & (y[:-1] != 0)))
    f = lambda tt: float(s.spline(tt)[0]) - level   # noqa: E731
    return [float(brentq(f, s.t[j], s.t[j + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps))
            for j in idx]
