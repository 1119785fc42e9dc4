"""A breech's fatigue: its wall (a thick cylinder) and its steel's S-N
curve, a pressure history taken through the bore's hoop stress to a damage
by rainflow counting and Miner's rule; and the life a campaign's damages allow.

A blow that starts and ends at the rest pressure, as a drop-hammer blow
does, closes all its cycles with itself: the rainflow cycles of a campaign's
whole history are those of its blows, and its damage is the sum of theirs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from pdbfs.errors import DataError, ParameterError

from .counting import cycle_arrays, rainflow
from .cylinder import ThickCylinder
from .sn import GUN_STEEL_SN, SNCurve

if TYPE_CHECKING:
    import pandas as pd

BREECH_CYLINDER = ThickCylinder(inner_radius=0.08, outer_radius=0.16)
"""An assumed breech of a large-calibre gun (the paper gives no breech's
dimensions): a chamber of 160 mm diameter in a wall of radius ratio 2, so
that the bore's hoop stress is 5/3 of the pressure. Give your breech's own."""


@dataclass(frozen=True)
class Breech:
    """A breech: the wall the pressure acts in and the S-N curve of its
    steel, in the range of the bore's hoop stress.

    Parameters
    ----------
    cylinder : ThickCylinder, optional
        The wall (default :data:`BREECH_CYLINDER`, an assumed large-calibre
        breech: bore radius 0.08 m, outer radius 0.16 m).
    curve : SNCurve, optional
        The S-N curve of the bore's hoop stress range (default
        :data:`GUN_STEEL_SN`, an engineering estimate for a gun steel).

    Examples
    --------
    The damage of a blow of the paper rig, from its whole pressure history
    and from its summary's peak alone (one cycle from rest to peak):

    >>> from pdbfs.fatigue import Breech
    >>> from pdbfs.models import paper_rig
    >>> breech = Breech()
    >>> res = paper_rig().simulate(0.02)
    >>> d = breech.damage(res)                    # the pressure's every cycle
    >>> d1 = breech.peak_damage(res.summary()["peak_pressure"])
    >>> 1 < d / d1 < 1.01                         # the ripples on the pulse add a little
    True
    """

    cylinder: ThickCylinder = BREECH_CYLINDER
    curve: SNCurve = GUN_STEEL_SN

    def __post_init__(self):
        if not isinstance(self.cylinder, ThickCylinder):
            raise ParameterError(f"Breech: cylinder must be a ThickCylinder, not "
                                 f"{type(self.cylinder).__name__}")
        if not isinstance(self.curve, SNCurve):
            raise ParameterError(f"Breech: curve must be an SNCurve, not "
                                 f"{type(self.curve).__name__}")

    def stress_cycles(self, history: Any, signal: str | None = None) -> "pd.DataFrame":
        """The rainflow cycles of the bore's hoop stress under a pressure history.

        Parameters
        ----------
        history : array_like, (t, p), trace or Result
            The pressure, Pa, in time order (as :func:`pdbfs.fatigue.rainflow` takes it).
        signal : str, optional
            The pressure variable of a Result (default: its one variable in Pa).

        Returns
        -------
        pandas.DataFrame
            Columns ``range`` and ``mean`` (hoop stress, Pa) and ``count``.
        """
        cycles = rainflow(history, signal)
        k = self.cylinder.bore_factor          # the stress is linear in the pressure
        cycles["range"] *= k
        cycles["mean"] *= k
        return cycles

    def damage(self, history: Any, signal: str | None = None) -> float:
        """Miner's damage of a pressure history: one blow's, a campaign's, a firing's.

        Parameters
        ----------
        history : array_like, (t, p), trace or Result
            The pressure, Pa, in time order.
        signal : str, optional
            The pressure variable of a Result (default: its one variable in Pa).

        Returns
        -------
        float
            The damage (1: failure by Miner's rule).
        """
        ranges, _, counts = cycle_arrays(history, signal)
        return self.curve.damage({"range": ranges * self.cylinder.bore_factor, "count": counts})

    def peak_damage(self, peak_pressure: Any, rest_pressure: Any = 0.0) -> float | np.ndarray:
        """The damage of one cycle from the rest pressure to a peak: a blow
        read off its summary (``peak_pressure``, or a multi-blow rig's
        ``impact_peak_pressures``), the ripples on its pulse left out.

        Parameters
        ----------
        peak_pressure : float or array_like
            The peak pressure of each blow, Pa.
        rest_pressure : float or array_like, optional
            The pressure each blow starts from and returns to, Pa (default 0).

        Returns
        -------
        float or numpy.ndarray
            The damage of each blow.

        Raises
        ------
        pdbfs.DataError
            For a peak below its rest pressure, or values not finite.
        """
        peak = np.asarray(peak_pressure, dtype=float)
        rest = np.asarray(rest_pressure, dtype=float)
        if not (np.all(np.isfinite(peak)) and np.all(np.isfinite(rest))):
            raise DataError("Breech.peak_damage: the peak and rest pressures must be finite "
                            "numbers (a blow whose summary has no peak has no damage to read)")
        if np.any(peak < rest):
            raise DataError("Breech.peak_damage: a peak pressure is below its rest pressure")
        d = 1.0 / self.curve.cycles_to_failure(self.cylinder.bore_hoop_stress(peak - rest))
        return float(d) if np.ndim(d) == 0 else d


def campaign_life(damages: Any) -> float:
    """The predicted life, in blows, of a breech that runs a campaign again
    and again: the blows after which Miner's sum reaches 1, the last
    repetition cut where it does (its blows in their order).

    Parameters
    ----------
    damages : array_like
        The damage of each blow of the campaign, in order (0 or more).

    Returns
    -------
    float
        The blows to failure (``inf`` if the campaign does no damage). For
        one blow repeated it is ``1 / damage``; the campaigns to failure
        are ``1 / sum(damages)``.

    Raises
    ------
    pdbfs.DataError
        For no damages, or damages that are negative or not finite.

    Examples
    --------
    >>> from pdbfs.fatigue import campaign_life
    >>> campaign_life([1e-4, 3e-4])              # 2500 campaigns of 2 blows
    5000.0
    """
    d = np.asarray(damages, dtype=float).ravel()
    if d.size == 0:
        raise DataError("campaign_life: a campaign needs at least one blow's damage")
    if not np.all(np.isfinite(d)) or np.any(d < 0):
        raise DataError("campaign_life: the damages must be finite numbers, 0 or more")
    total = float(np.sum(d))
    if total == 0.0:
        return math.inf
    whole = math.floor(1.0 / total)             # whole campaigns survived
    left = 1.0 - whole * total
    if left >= total * (1 - 1e-12):             # 1 / total rounded down a campaign short
        whole, left = whole + 1, left - total
    if left <= total * 1e-12:                   # failure at the end of a whole campaign
        return float(whole * d.size)
    reached = np.cumsum(d)
    # the blow of the last campaign that fails it
    k = min(int(np.searchsorted(reached, left)), d.size - 1)
    before = reached[k - 1] if k else 0.0
    return float(whole * d.size + k + (left - before) / d[k])
