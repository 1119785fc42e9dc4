"""The summary of a run: what a test engineer reads off a pressure pulse.

A rig names the variables that play each role in ``summary_signals``
(``pressure``, ``contact_force``, ``piston_displacement``,
``striker_velocity``, and for rigs whose hammer strikes more than once
``impact_indentation``); the compiled DAE
carries that mapping as ``dae.signals``.
"""
from __future__ import annotations

import numpy as np

from pdbfs.components.laws import restitution_from_force

KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
        "max_piston_displacement", "restitution_coefficient")
UNITS = {"peak_pressure": "Pa", "time_of_peak": "s", "pulse_duration": "s",
         "peak_contact_force": "N", "max_piston_displacement": "m",
         "restitution_coefficient": "1",
         # rigs with the role impact_indentation (repeated blows): lists, one per blow
         "impact_count": "1", "impact_times": "s", "impact_peak_pressures": "Pa"}

PULSE_LEVEL = 0.01   # the pulse lasts while the pressure exceeds 1 % of its peak


def keys_for(dae) -> list[str]:
    """The summary keys of a rig, in order, from the roles it names."""
    roles = getattr(dae, "signals", {}) or {}
    keys = []
    if roles.get("pressure"):
        keys += ["peak_pressure", "time_of_peak", "pulse_duration"]
    if roles.get("contact_force"):
        keys.append("peak_contact_force")
    if roles.get("piston_displacement"):
        keys.append("max_piston_displacement")
    if roles.get("contact_force"):
        keys.append("restitution_coefficient")
    if roles.get("impact_indentation"):
        keys += ["impact_count", "impact_times"] + (["impact_peak_pressures"]
                                                   if roles.get("pressure") else [])
    return keys


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
        out["restitution_coefficient"] = restitution(res, f, roles.get("striker_velocity"))
    d = roles.get("impact_indentation")
    if d:
        out.update(blows(res, d, p))
    return out


def blows(res, indentation, pressure=None) -> dict:
    """Every blow of a hammer that strikes repeatedly. Contacts start where
    ``indentation`` crosses 0 upwards (located by root finding); contacts
    follow one another within one blow (the hammer chatters on the piston);
    once the pressure has risen above PULSE_LEVEL of its overall peak and
    fallen below it again, the next contact starts a new blow. Returns impact_count,
    impact_times (first contact of each blow) and impact_peak_pressures."""
    d = res[indentation]
    # a crossing lies between two samples of opposite sign: upwards if the later one is > 0
    onsets = [float(tt) for tt in res.crossings(indentation, 0.0)
              if d[min(int(np.searchsorted(res.t, tt)), len(d) - 1)] > 0]
    if d[0] > 0:
        onsets.insert(0, float(res.t[0]))
    if not pressure:
        return {"impact_count": len(onsets), "impact_times": onsets}
    y = res[pressure]
    level = PULSE_LEVEL * float(np.max(y))
    starts, prev = [], None
    for tt in onsets:
        if prev is not None:   # a new blow only once the previous pulse has risen and fallen
            k0, k1 = np.searchsorted(res.t, [prev, tt])
            above = y[k0:k1] >= level
            ended = above.any() and not above[int(np.argmax(above)):].all()
            prev = tt
            if not ended:
                continue
        starts.append(tt)
        prev = tt
    edges = np.searchsorted(res.t, starts + [res.t[-1] + 1.0])
    peaks = []
    for k0, k1 in zip(edges[:-1], edges[1:]):
        k1 = max(min(k1, len(y)), k0 + 1)
        peaks.append(_local_peak(res, pressure, k0, k1))
    return {"impact_count": len(starts), "impact_times": [float(s) for s in starts],
            "impact_peak_pressures": peaks}


def _local_peak(res, name, k0, k1) -> float:
    """Maximum of ``name`` over output samples k0..k1-1, refined on the solution."""
    return res.peak(name, window=(res.t[k0], res.t[k1 - 1]))[1]


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


def restitution(res, name, striker_velocity=None) -> float | None:
    """Guo & Batzer's impulse ratio (paper eq. 8) for the first blow.

    The paper's restitution phase starts at maximum indentation; Guo & Batzer
    take the force peak for that instant, which holds for a single hump. The
    PDBFS blow is many humps, and its force peaks well before the hammer
    stops, so with a ``striker_velocity`` role the split is where the striker
    stops, over every contact until it turns back (or the run ends). Without
    it: the first contact, split at its force peak. None where not defined
    (no contact, or the striker has not stopped by the end of the run)."""
    f = res[name]
    if not np.any(f > 0):
        return None          # no contact: not defined
    if striker_velocity:
        v = res[striker_velocity]
        turns = res.crossings(striker_velocity, 0.0)
        down_up = [tt for tt in turns if v[min(np.searchsorted(res.t, tt), len(v) - 1)] < 0]
        if not down_up:
            return None
        t_stop = float(down_up[0])
        later = [tt for tt in turns if tt > t_stop]
        t_back = float(later[0]) if later else float(res.t[-1])   # the apex of the rebound
        before = res.curves.integral(name, res.t[0], t_stop)
        if before is not None:            # on the Hermite interpolant: no grid error
            after = res.curves.integral(name, t_stop, t_back)
            return float(after / before) if before > 0 else None
        t, y = _with_point(res, name, t_stop)
        k = int(np.searchsorted(t, t_stop))            # the inserted sample
        j = int(np.searchsorted(t, t_back, side="right"))
        before = np.trapezoid(y[:k + 1], t[:k + 1])
        after = np.trapezoid(y[k:j], t[k:j])
        return float(after / before) if before > 0 else None
    on = np.flatnonzero(f > 0)
    gap = np.flatnonzero(f[on[0]:] <= 0)
    k_end = on[0] + gap[0] if gap.size else len(f) - 1
    t_pk = res.peak(name, window=(res.t[on[0]], res.t[k_end]))[0]
    t, y = _with_point(res, name, t_pk)
    return restitution_from_force(t, y, t_split=t_pk)


def _with_point(res, name, tt):
    """The sampled history of ``name`` with its exact value at ``tt`` inserted."""
    k = int(np.searchsorted(res.t, tt))
    return (np.insert(res.t, k, tt),
            np.insert(res[name], k, max(res.value_at(name, tt), 0.0)))
