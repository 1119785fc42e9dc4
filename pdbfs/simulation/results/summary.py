"""The summary of a run: what a test engineer reads off a pressure pulse.

A rig names the variables that play each role in ``summary_signals``
(``pressure``, ``contact_force``, ``piston_displacement``,
``striker_velocity``, and for rigs whose hammer strikes more than once
``impact_indentation``); the compiled DAE carries that mapping as
``dae.signals``.

Every figure is located on the summary's own solution (summary_run.py),
never read off the caller's output grid, and belongs to the first blow:
from t = 0 until the pulse is over (the pressure back under PULSE_LEVEL of
its peak and the bodies apart) or the horizon. ``complete`` says whether the
pulse ended inside the horizon; where it did not, the figures that need its
end (duration, restitution) are None and a PulseIncompleteWarning names the
horizon that would hold it. Rigs that strike repeatedly also list every
blow (impact_times, impact_peak_pressures, impact_durations).
"""
from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import ImplausibleResultWarning, PdbfsWarning, PulseIncompleteWarning

from . import contact_impulse
from .summary_run import PULSE_LEVEL, has_pulse, pulse_level, summary_run

if TYPE_CHECKING:
    from .result import Result

KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
        "max_piston_displacement", "restitution_coefficient", "complete")
UNITS = {"peak_pressure": "Pa", "time_of_peak": "s", "pulse_duration": "s",
         "peak_contact_force": "N", "max_piston_displacement": "m",
         "restitution_coefficient": "1", "complete": "",
         # rigs with the role impact_indentation (repeated blows): lists, one per blow
         "impact_count": "1", "impact_times": "s", "impact_peak_pressures": "Pa",
         "impact_durations": "s"}

MAX_POINTS_NOTE = "a bounded number of points in memory"

__all__ = ["KEYS", "UNITS", "PULSE_LEVEL", "keys_for", "summarize"]


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
    if roles.get("pressure") or roles.get("contact_force"):
        keys.append("complete")
    if roles.get("impact_indentation"):
        keys += ["impact_count", "impact_times"] + (["impact_peak_pressures", "impact_durations"]
                                                   if roles.get("pressure") else [])
    return keys


def summarize(res: Result, warn: bool = True) -> dict:
    """The summary of a run, located on the summary's own solution
    (``Result.summary`` gives it, computed once).

    Parameters
    ----------
    res : Result
        The run.
    warn : bool
        Whether to warn (PulseIncompleteWarning) when the pulse outlasts the run.

    Returns
    -------
    dict
        Figure name (``SUMMARY_KEYS``, and the blows of a rig that strikes
        more than once) -> value in its SI unit (``SUMMARY_UNITS``); None
        for a figure the run cannot give.
    """
    roles = getattr(res._sim.dae, "signals", {}) or {}
    run = summary_run(res)
    R = run.trajectory
    p, f = roles.get("pressure"), roles.get("contact_force")
    blow = (0.0, R.t[-1])
    blow_list = None
    d = roles.get("impact_indentation")
    if d:
        blow_list = blows(R, d, p, run.base, run.peak_after)
        if blow_list["impact_count"] > 1:
            blow = (0.0, blow_list["impact_times"][1])
    out, cut = {}, []
    complete = run.complete
    if p:
        t_pk, p_pk = R.peak(p, window=blow)
        pulse = bool(run.pulse)
        # the highest pressure so far is no peak when the pulse rises higher after t_end,
        # nor when it lies at t_end (still rising there, whatever the first sample past
        # it shows: the peak can fall between the two)
        last = blow[1] >= R.t[-1]
        higher = run.peak_after > p_pk
        rising = complete is False and t_pk >= R.t[-1] * (1 - 1e-9)
        at_end = pulse and last and (higher or rising)
        if at_end and higher:
            cut.append(f"its highest pressure so far, {p_pk:.4g} Pa, is not its peak: it rises "
                       f"to {run.peak_after:.4g} Pa after t_end")
        elif at_end:
            cut.append(f"the pressure still rises at t_end ({p_pk:.4g} Pa): its peak is later")
        out["peak_pressure"] = p_pk if pulse and not at_end else None
        out["time_of_peak"] = t_pk if pulse and not at_end else None
        out["pulse_duration"] = time_above(R, p, pulse_level(run.base, p_pk), blow) \
            if pulse and complete else None
        if blow_list is not None and blow_list.get("cut_last"):
            complete = False
            cut.append(f"blow {blow_list['impact_count']} (at "
                       f"{blow_list['impact_times'][-1]:.4g} s) is cut off at t_end")
    horizon = blow[1] >= R.t[-1] and complete is False     # a maximum there is no peak
    if f:
        t_f, f_pk = R.peak(f, window=blow)
        out["peak_contact_force"] = None if horizon and f_pk > 0 and \
            t_f >= R.t[-1] * (1 - 1e-9) else max(f_pk, 0.0)
    s = roles.get("piston_displacement")
    if s:
        t_s, s_pk = R.peak(s, window=blow)
        out["max_piston_displacement"] = None if horizon and t_s >= R.t[-1] * (1 - 1e-9) \
            else s_pk
    if f:
        out["restitution_coefficient"] = restitution(R, f, roles.get("striker_velocity"),
                                                     blow, run.impulse) if run.complete else None
    if complete is not None:
        out["complete"] = bool(complete)
    if blow_list is not None:
        blow_list.pop("cut_last", None)
        out.update(blow_list)
    if warn and p and run.pulse is False:
        warnings.warn(f"rig {res._sim.dae.name}: no pulse: the pressure does not rise above "
                      f"its start value {run.base:.6g} Pa in [0, {run.t_end:.6g}] s",
                      PulseIncompleteWarning, stacklevel=3)
    elif warn and run.complete is False:
        warnings.warn(incomplete_message(res, run, cut), PulseIncompleteWarning, stacklevel=3)
    elif warn and cut:
        warnings.warn(f"rig {res._sim.dae.name}: {'; '.join(cut)} (t_end = {run.t_end:.6g} s)",
                      PulseIncompleteWarning, stacklevel=3)
    if warn and run.listed_until is not None:
        warnings.warn(f"rig {res._sim.dae.name}: blows are listed up to t = "
                      f"{run.listed_until:.6g} s of {run.t_end:.6g} s (the summary keeps "
                      f"{MAX_POINTS_NOTE}); the first blow's figures are whole",
                      PdbfsWarning, stacklevel=3)
    return out


def incomplete_message(res, run, cut=()) -> str:
    """The warning for a pulse still running at t_end: where it ends, if the run saw it."""
    where = f"rig {res._sim.dae.name}: the pulse is still running at t_end = {run.t_end:.6g} s"
    if cut:
        where += f" ({'; '.join(cut)})"
    if run.t_done is not None:
        need = _round_up(1.2 * run.t_done)
        return (f"{where}: it ends at about {run.t_done:.4g} s; use t_end >= {need:.3g} s "
                "(duration and restitution are not reported)")
    return (f"{where} and has not ended by {run.looked_until:.4g} s "
            "(duration and restitution are not reported)")


def _round_up(x: float) -> float:
    e = 10.0 ** np.floor(np.log10(x))
    return float(np.ceil(x / e * 10) / 10 * e)


def time_above(R, name, level, window) -> float:
    """Total time within ``window`` during which ``name`` exceeds ``level``:
    crossings located on the solution, paired by direction."""
    a, b = window
    y = R[name]
    # the sample after a crossing tells its direction (crossings lie between samples)
    up = lambda tc: y[min(int(np.searchsorted(R.t, tc)), len(y) - 1)] > level  # noqa: E731
    total, start = 0.0, (a if R.value_at(name, a) > level else None)
    for tc in R.crossings(name, level):
        if not a < tc < b:
            continue
        if start is None and up(tc):
            start = tc
        elif start is not None and not up(tc):
            total += tc - start
            start = None
    if start is not None:
        total += b - start
    return float(total)


def implausible(res: Result, out: dict) -> list:
    """The warnings (recorded, as ``warnings.catch_warnings(record=True)``
    gives them) of the run ``res`` and its summary ``out`` where a figure
    lies outside its physical range, each naming the likely cause: a
    restitution coefficient above 1 (the blow gives back more energy than
    it took) comes from bodies that start interpenetrating (the contact
    force is already up at t = 0) or else from tolerances too loose for the
    blow; a pressure of an oil circuit fed by pressure sources alone above
    every source's and start pressure (modelling.pressure_bound) from
    tolerances too loose for the circuit. Empty where every figure is
    plausible.

    Parameters
    ----------
    res : Result
        The run.
    out : dict
        Its summary (Result.summary()'s keys).

    Returns
    -------
    list of warnings.WarningMessage
        ImplausibleResultWarning records, to be given with the summary.
    """
    dae, s = res._sim.dae, res.settings
    e, bound = out.get("restitution_coefficient"), getattr(dae, "pressure_bound", None)
    if not (e is not None and e > 1.0) and not bound:
        return []
    loose = (f"the solution is not accurate enough: rtol = {s['rtol']:g}, atol = {s['atol']:g} "
             "are too loose for this run (try the defaults, or a tighter rtol)")
    found = []
    if e is not None and e > 1.0:
        force = (getattr(dae, "signals", {}) or {}).get("contact_force")
        f0 = float(res[force][0]) if force else 0.0
        cause = (f"the contact force is already {f0:.4g} N at t = 0: the bodies start "
                 "interpenetrating (a negative gap?), and the blow releases the energy stored "
                 "in the contact" if f0 > 0 else loose)
        found.append(f"rig {dae.name}: the restitution coefficient {e:.6g} is above 1 (the "
                     f"blow would give back more energy than it took): {cause}")
    if bound:
        found += _above_sources(res, bound, s, loose)
    if not found:                 # (the usual case: no warnings machinery)
        return []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for text in found:
            warnings.warn(text, ImplausibleResultWarning, stacklevel=2)
    return caught


def _above_sources(res, bound, s, loose) -> list:
    """The warning of a circuit's pressure above every bound of it (or none):
    beyond ten tolerances' share of the bound, which an accurate run stays within."""
    top = max([res.peak(n)[1] for n in bound["sources"]] + [float(res[n][0]) for n in bound["stores"]])
    peak, where = max((res.peak(n)[1], n) for n in bound["stores"]) if bound["stores"] else (-np.inf, "")
    if not peak > top + 10.0 * (s["rtol"] * abs(top) + s["atol"]):
        return []
    return [f"rig {res._sim.dae.name}: {where} reaches {peak:.10g} Pa, above every source's and "
            f"start pressure of its circuit (at most {top:.10g} Pa): {loose}"]


def restitution(R, force, striker_velocity=None, window=None, impulse=None) -> float | None:
    """Guo & Batzer's impulse ratio (paper eq. 8) for the first blow.

    The paper's restitution phase starts at maximum indentation; Guo & Batzer
    take the force peak for that instant, which holds for a single hump. The
    PDBFS blow is many humps, and its force peaks well before the hammer
    stops, so with a ``striker_velocity`` role the split is where the striker
    stops, over every contact until it turns back (or the blow ends). Without
    it: the first contact, split at its force peak. The split is located on
    the solution, and the impulses are the solver's (``impulse``: a
    function giving the force's impulse on R.t, summary_run.py; None: it is
    integrated on R.t here), taken between output points by a short
    integration (contact_impulse.py): a contact shorter than the output step
    counts whole. As accurate as the striker's velocity: at the default
    tolerances within 1e-6 of an event-located reference for contacts from
    1 us to 8 ms, on either back end.
    None where not defined (no contact, or the striker has not stopped)."""
    a, b = window if window is not None else (R.t[0], R.t[-1])
    if striker_velocity:
        v = R[striker_velocity]
        turns = [tt for tt in R.crossings(striker_velocity, 0.0) if a < tt < b]
        after = lambda tt: v[min(np.searchsorted(R.t, tt), len(v) - 1)]   # noqa: E731
        stops = [tt for tt in turns if after(tt) < 0]
        if not stops:
            return None
        t_stop = float(stops[0])
        back = [tt for tt in turns if tt > t_stop]
        t_back = float(back[0]) if back else float(b)   # the apex of the rebound
        return _ratio(R, force, impulse, a, t_stop, t_back)
    f = R[force]
    if not np.any(f > 0):
        return None
    on = np.flatnonzero(f > 0)
    gap = np.flatnonzero(f[on[0]:] <= 0)
    k_end = on[0] + gap[0] if gap.size else len(f) - 1
    t_on = float(R.t[max(on[0] - 1, 0)])
    t_pk = R.peak(force, window=(t_on, R.t[k_end]))[0]
    return _ratio(R, force, impulse, t_on, t_pk, float(R.t[k_end]))


def _ratio(R, force, impulse, a, t_split, b) -> float | None:
    """The impulse of ``force`` over [t_split, b] over its impulse over
    [a, t_split], on the solution."""
    Q = impulse() if impulse is not None else \
        contact_impulse.on_grid(R._sim, R.t, R._X[:, 0], R.p, R.settings, force)[2]
    q_a, q_split, q_b = (contact_impulse.impulse_at(R, Q, force, t) for t in (a, t_split, b))
    before, after = q_split - q_a, q_b - q_split
    if not (np.isfinite(before) and np.isfinite(after)) or before <= 0:
        return None
    return float(after / before)


def blows(R, indentation, pressure=None, base=0.0, peak_after=-np.inf) -> dict:
    """Every blow of a hammer that strikes repeatedly. Contacts start where
    ``indentation`` crosses 0 upwards; contacts follow one another within
    one blow (the hammer chatters on the piston); once the pressure has risen
    above PULSE_LEVEL of its overall peak and fallen below it again, the next
    contact starts a new blow. Returns impact_count, impact_times (first
    contact of each blow), and with a pressure impact_peak_pressures and
    impact_durations (None for a blow cut off by the horizon; its peak too
    when the pressure rises higher after it, ``peak_after``), all above the
    start pressure ``base``; ``cut_last`` says whether the last blow is cut off."""
    d = R[indentation]
    onsets = [float(tt) for tt in R.crossings(indentation, 0.0)
              if d[min(int(np.searchsorted(R.t, tt)), len(d) - 1)] > 0]
    if d[0] > 0:
        onsets.insert(0, float(R.t[0]))
    if not pressure:
        return {"impact_count": len(onsets), "impact_times": onsets}
    y = R[pressure]
    level = pulse_level(base, float(np.max(y)))
    starts, prev = [], None
    for tt in onsets:
        if prev is not None:   # a new blow only once the previous pulse has risen and fallen
            k0, k1 = np.searchsorted(R.t, [prev, tt])
            above = y[k0:k1] >= level
            ended = above.any() and not above[int(np.argmax(above)):].all()
            prev = tt
            if not ended:
                continue
        starts.append(tt)
        prev = tt
    ends = starts[1:] + [float(R.t[-1])]
    peaks, durations, cut = [], [], False
    for i, (a, b) in enumerate(zip(starts, ends)):
        t_pk, p_pk = R.peak(pressure, window=(a, b))
        last = i == len(starts) - 1
        rose = has_pulse(base, p_pk)
        if i == 0 and d[0] > 0 and not rose:       # resting in contact from the start: no blow
            continue
        higher = last and peak_after > p_pk       # its peak lies past the horizon
        cut = last and (not rose or higher or y[-1] >= pulse_level(base, p_pk))
        peaks.append(None if higher or not rose else p_pk)     # no rise: no peak (at rest)
        durations.append(None if cut or not rose else
                         time_above(R, pressure, pulse_level(base, p_pk), (a, b)))
    starts = starts[len(starts) - len(peaks):]
    return {"impact_count": len(starts), "impact_times": [float(s) for s in starts],
            "impact_peak_pressures": peaks, "impact_durations": durations,
            "cut_last": bool(cut and len(starts) > 1)}
