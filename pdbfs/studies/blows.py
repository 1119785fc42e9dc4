"""A rig's blows as a breech's fatigue sees them: the damage of one blow
(its pressure history through pdbfs.fatigue, its reversals located on the
solution), and the drop height whose blow does a given damage (one gun
firing's, say).

The drop height is that of the rig's own parameter (the drop rig's ``h``)
or stands for its striker's impact speed, ``v0 = sqrt(2 g h)`` (the paper
rig's ``hammer.v0``). It is found by Brent's method on the logarithm of the
damage, once the damage has been seen to grow with the height at every one
of a set of heights across the range searched; a damage outside the range's
reach, or a damage that does not grow with the height, gives no height and
says why.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.components.laws import STANDARD_GRAVITY
from pdbfs.errors import ParameterError
from pdbfs.fatigue import Breech

if TYPE_CHECKING:
    from pdbfs.modelling import DAE
    from pdbfs.rig import Rig
    from pdbfs.simulation import Result

#: heights at which the damage is checked to grow before the root is sought
CHECKS = 9


def blow_damage(rig: Rig, breech: Breech | None = None, params: dict | None = None,
                t_end: float | None = None, backend: str = "auto") -> tuple[float, Result]:
    """The damage one blow of ``rig`` does to ``breech``, and its Result.

    Parameters
    ----------
    rig : pdbfs.Rig
        A rig that names its pressure (``summary_signals``).
    breech : pdbfs.fatigue.Breech, optional
        The breech (default: ``Breech()``, an assumed large-calibre breech).
    params : dict, optional
        Parameters of the run ({name: value}).
    t_end : float, optional
        Simulated time, s (default: the rig's own); the pulse must end inside it.
    backend : str, optional
        As for :meth:`pdbfs.Rig.simulate`.

    Returns
    -------
    (float, pdbfs.Result)
        The blow's damage by Miner's rule and the run it was read from.

    Raises
    ------
    pdbfs.ParameterError
        For a rig without a pressure.
    pdbfs.DataError
        For a pulse still running at ``t_end``.
    """
    breech = Breech() if breech is None else breech
    dae = rig.compile()
    pressure = (getattr(dae, "signals", {}) or {}).get("pressure")
    if not pressure:
        raise ParameterError(f"rig {dae.name} names no pressure (summary_signals): its blows "
                             "have no pressure history to take to a damage")
    t_end = t_end if t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = getattr(rig, "default_n_out", 2001)
    res = rig.simulate(t_end, n_out=n_out, params=params or {}, backend=backend)
    return breech.damage(res, signal=pressure), res


def height_parameter(dae: DAE) -> tuple[str, bool] | None:
    """(the rig parameter a drop height sets, whether it is an impact speed
    ``v0 = sqrt(2 g h)`` rather than the height itself), or None for a rig
    with neither (no striker)."""
    own = [p.name for p in dae.params
           if p.unit == "m" and p.description.lower().startswith("drop height")]
    if own:
        return own[0], False
    striker = (getattr(dae, "signals", {}) or {}).get("striker_velocity")
    if striker and "." in striker:
        speed = striker.rsplit(".", 1)[0] + ".v0"
        if speed in dae.p_names:
            return speed, True
    return None


@dataclass
class HeightSearch:
    """The drop height whose blow does a target damage.

    Attributes
    ----------
    height : float or None
        The drop height, m (None: not found; ``note`` says why).
    parameter : str
        The rig parameter it sets.
    value : float or None
        That parameter's value: the height, or the impact speed ``sqrt(2 g h)``, m/s.
    damage : float or None
        The damage of a blow from ``height`` (the target's, to Brent's tolerance).
    note : str
        Why no height was found ("" when it was).
    heights, damages : list of float
        The heights checked across the range, m, and their blows' damages.
    """

    height: float | None
    parameter: str
    value: float | None
    damage: float | None
    note: str = ""
    heights: list = field(default_factory=list)
    damages: list = field(default_factory=list)


def height_for_damage(rig: Rig, target: float, breech: Breech | None = None,
                      heights: tuple[float, float] = (0.01, 5.0), params: dict | None = None,
                      t_end: float | None = None, backend: str = "auto") -> HeightSearch:
    """The drop height whose blow of ``rig`` does the damage ``target``.

    Parameters
    ----------
    rig : pdbfs.Rig
        A rig with a drop height of its own, or a striker with an impact speed ``X.v0``.
    target : float
        The damage a blow is to do (> 0), e.g. a gun firing's.
    breech : pdbfs.fatigue.Breech, optional
        The breech (default: ``Breech()``).
    heights : (float, float), optional
        The drop heights searched, m (default 0.01 to 5).
    params : dict, optional
        Other parameters of the runs (the height's own parameter is set by the search).
    t_end : float, optional
        Simulated time of each blow, s (default: the rig's own).
    backend : str, optional
        As for :meth:`pdbfs.Rig.simulate`.

    Returns
    -------
    HeightSearch
        The height and its blow's damage, or None and why.

    Raises
    ------
    pdbfs.ParameterError
        For a rig without a drop height or an impact speed, a target that is
        not positive, or heights that are not 0 < lo < hi.
    """
    from scipy.optimize import brentq
    breech = Breech() if breech is None else breech
    dae = rig.compile()
    found = height_parameter(dae)
    if found is None:
        raise ParameterError(f"rig {dae.name} has no drop height and no striker's impact speed "
                             "(X.v0): no drop height does a damage")
    name, speed = found
    if not (isinstance(target, (int, float)) and math.isfinite(target) and target > 0):
        raise ParameterError(f"the target damage must be a positive number, not {target!r}")
    lo, hi = (float(h) for h in heights)
    if not (0 < lo < hi and math.isfinite(hi)):
        raise ParameterError(f"drop heights {lo:g}:{hi:g} m: give 0 < LO < HI")
    value = (lambda h: math.sqrt(2.0 * STANDARD_GRAVITY * h)) if speed else (lambda h: h)
    fixed = {k: v for k, v in (params or {}).items() if k != name}

    def damage(h):
        return blow_damage(rig, breech, {**fixed, name: value(h)}, t_end, backend)[0]

    hs = list(np.geomspace(lo, hi, CHECKS))
    ds = [damage(h) for h in hs]
    out = HeightSearch(None, name, None, None, heights=[float(h) for h in hs],
                       damages=[float(d) for d in ds])
    if not all(b > a for a, b in zip(ds, ds[1:])):
        out.note = (f"the blow's damage does not grow with the drop height across {lo:g} to "
                    f"{hi:g} m (checked at {CHECKS} heights): no single height")
        return out
    if not ds[0] <= target <= ds[-1]:
        side = "below" if target < ds[0] else "above"
        out.note = (f"a damage of {target:.4g} is {side} what blows from {lo:g} to {hi:g} m do "
                    f"({ds[0]:.4g} to {ds[-1]:.4g}); widen the heights searched")
        return out
    k = next(i for i in range(CHECKS - 1) if ds[i] <= target <= ds[i + 1])
    if ds[k] == target or ds[k + 1] == target:
        h = hs[k] if ds[k] == target else hs[k + 1]
    else:
        h = brentq(lambda x: math.log(damage(x) / target), hs[k], hs[k + 1],
                   xtol=1e-12, rtol=1e-10)
    out.height, out.value, out.damage = float(h), float(value(h)), float(damage(h))
    return out
