"""The summary of a run: what a test engineer reads off a pressure pulse.

A rig names the variables that play each role in ``summary_signals``
(``pressure``, ``contact_force``, ``piston_displacement``); the compiled DAE
carries that mapping as ``dae.signals``.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from pdbfs.components.laws import restitution_from_force

KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
        "max_piston_displacement", "restitution_coefficient")
UNITS = {"peak_pressure": "Pa", "time_of_peak": "s", "pulse_duration": "s",
         "peak_contact_force": "N", "max_piston_displacement": "m",
         "restitution_coefficient": "1"}

PULSE_LEVEL = 0.01   # the pulse lasts while the pressure exceeds 1 % of its peak


def summarize(res) -> dict:
    roles = getattr(res._sim.dae, "signals", {}) or {}
    out = {}
    p = roles.get("pressure")
    if p:
        t_pk, p_pk = res.peak(p)
        out["peak_pressure"] = p_pk
        out["time_of_peak"] = t_pk
        out["pulse_duration"] = time_above(res, p, PULSE_LEVEL * p_pk)
    f = roles.get("contact_force")
    if f:
        out["peak_contact_force"] = res.peak(f)[1]
    s = roles.get("piston_displacement")
    if s:
        out["max_piston_displacement"] = res.peak(s)[1]
    if f:
        out["restitution_coefficient"] = restitution(res, f)
    return out


def time_above(res, name, level) -> float:
    """Total time during which ``name`` exceeds ``level`` (crossings located
    by root finding)."""
    y = res[name]
    times = [res.t[0]] if y[0] > level else []
    times += list(res.crossings(name, level))
    if y[-1] > level:
        times.append(res.t[-1])
    times = np.asarray(times)
    return float(np.sum(times[1::2] - times[0::2])) if times.size else 0.0


def restitution(res, name) -> float:
    """Guo & Batzer's estimate on the first contact (the hammer may strike
    again), the split at the force peak located precisely and added to the
    sampled history."""
    f = res[name]
    on = np.flatnonzero(f > 0)
    if on.size == 0:
        return float("nan")
    gap = np.flatnonzero(f[on[0]:] <= 0)
    k_end = on[0] + gap[0] if gap.size else len(f) - 1
    k_pk = on[0] + int(np.argmax(f[on[0]:k_end + 1]))
    a, b = res.t[max(k_pk - 1, 0)], res.t[min(k_pk + 1, len(f) - 1)]
    r = minimize_scalar(lambda tt: -res.value_at(name, tt), bounds=(a, b), method="bounded",
                        options={"xatol": 1e-13})
    t = np.insert(res.t, k_pk + (r.x > res.t[k_pk]), r.x)
    y = np.insert(f, k_pk + (r.x > res.t[k_pk]), -r.fun)
    return restitution_from_force(t, y)
