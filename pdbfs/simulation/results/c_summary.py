"""The summary of a compiled run from the run itself: the compiled backend
integrates the output grid and records every step in one call
(native/c/library/pdbfs_run_summary.c), and the summary driver's reduction of that record
(native/c/library/pdbfs_summary.c: peaks where the slope turns, crossings of the pulse
level, CVODE's root finding on the recorded steps) gives Result.summary()
without integrating again.

It is used where it gives what summary.py would: a rig whose summary roles
the driver has (no repeated blows), a pulse that ended inside the run, and
no note from the driver. Anything else (a pulse cut off at the horizon, no
pulse, a rig that strikes repeatedly) goes to summary.py, which follows the
run further and explains.
"""
from __future__ import annotations

from operator import itemgetter

from .summary import keys_for

#: what the summary driver computes, in its order (the compiled library's summary,
#: native/c/library/pdbfs_summary.c); a key is reported when its role exists.
#: ``complete`` is 1.0 when the pulse ended inside the run (the pressure rose above and fell
#: back below 1 % of its peak, and the contact force is zero at the end), else 0.0
SUMMARY_KEYS = ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
                "max_piston_displacement", "restitution_coefficient", "complete")

COMPLETE = SUMMARY_KEYS.index("complete")


def usable(dae, lib) -> bool:
    """Whether the driver's summary of this rig has every key summary.py gives."""
    ok = getattr(lib, "_summary_usable", None)
    if ok is None:
        keys = keys_for(dae)
        ok = lib._summary_usable = bool(keys) and set(keys) <= set(lib.summary_keys)
    return ok


def _layout(sim) -> tuple:
    """(the rig's summary keys, a function picking their values from
    SUMMARY_KEYS' order as a tuple), once per rig (its RigState)."""
    keys = tuple(keys_for(sim.dae))
    at = [SUMMARY_KEYS.index(k) for k in keys]
    layout = sim.state.summary_layout = (keys, lambda v: tuple(v[i] for i in at)) \
        if len(at) < 2 else (keys, itemgetter(*at))
    return layout


def summary_of(sim, fast) -> dict | None:
    """Result.summary()'s dict from the run's own summary (values (a list),
    code, note), or None where summary.py must be asked (``sim``: the
    Simulator of the run)."""
    values, code, note = fast
    if code != 0 or note or values[COMPLETE] != 1.0:
        return None
    keys, pick = sim.state.summary_layout or _layout(sim)
    picked = pick(values)
    out = dict(zip(keys, picked))
    total = sum(picked)
    if total != total:                 # a NaN among them (undefined): which
        for k, x in out.items():
            if x != x:
                if k != "restitution_coefficient":
                    return None        # a figure summary.py would give: ask it
                out[k] = None
    if "complete" in out:
        out["complete"] = True
    return out
