"""Basquin's S-N curve and Miner's rule: the cycles a stress range allows,
and the damage a set of counted cycles does."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from pdbfs.errors import ParameterError

from .checks import cycles_table, positive


@dataclass(frozen=True)
class SNCurve:
    """An S-N curve of stress range (Basquin): ``N = cycles_ref *
    (stress_range_ref / range)**m``; a range at or below the endurance limit
    does no damage.

    The curve is one of stress *range* (twice the amplitude), for the mean
    stress of the cycles it is used for: no mean-stress correction is made.

    Parameters
    ----------
    m : float
        Basquin's exponent, the negative inverse slope of the curve in
        log-log axes (> 0).
    stress_range_ref : float
        A stress range on the curve, Pa (> 0).
    cycles_ref : float
        The cycles to failure at ``stress_range_ref`` (> 0).
    endurance_limit : float, optional
        The stress range, Pa, at or below which a cycle does no damage
        (default 0: every cycle does some).

    Raises
    ------
    pdbfs.ParameterError
        For a value that is not a finite number in its range (``m <= 0``, a
        reference range or cycle count that is not positive, a negative limit).

    Examples
    --------
    >>> from pdbfs.fatigue import SNCurve
    >>> curve = SNCurve(m=3.0, stress_range_ref=100e6, cycles_ref=1e6)
    >>> float(curve.cycles_to_failure(200e6))
    125000.0
    >>> curve.damage({"range": [200e6], "count": [1.0]})
    8e-06
    """

    m: float
    stress_range_ref: float
    cycles_ref: float
    endurance_limit: float = 0.0

    def __post_init__(self):
        owner = "SNCurve"
        for name, zero in (("m", False), ("stress_range_ref", False), ("cycles_ref", False),
                           ("endurance_limit", True)):
            object.__setattr__(self, name, positive(getattr(self, name), name, owner, zero=zero))

    def cycles_to_failure(self, stress_range: Any) -> float | np.ndarray:
        """The cycles to failure at a stress range (infinite at or below the
        endurance limit, and at a range of 0).

        Parameters
        ----------
        stress_range : float or array_like
            Stress ranges, Pa (0 or more).

        Returns
        -------
        float or numpy.ndarray
            The cycles to failure, of the shape of ``stress_range``.

        Raises
        ------
        pdbfs.ParameterError
            For a range that is negative or not a finite number.
        """
        s = np.asarray(stress_range, dtype=float)
        if not np.all(np.isfinite(s)) or np.any(s < 0):
            bad = s.ravel()[~(np.isfinite(s.ravel()) & (s.ravel() >= 0))][0]
            raise ParameterError(f"SNCurve.cycles_to_failure: stress range {bad:g} Pa must be a "
                                 "finite number, 0 or more")
        with np.errstate(divide="ignore"):
            n = self.cycles_ref * (self.stress_range_ref / s) ** self.m
        n = np.where(s <= self.endurance_limit, np.inf, n)
        return float(n) if n.ndim == 0 else n

    def damage(self, cycles: Any) -> float:
        """Miner's sum of counted cycles: the sum of count / N(range).

        Parameters
        ----------
        cycles : pandas.DataFrame or mapping
            Stress cycles with columns ``range`` (Pa) and ``count`` (as
            :func:`pdbfs.fatigue.rainflow` gives them, of a stress history).

        Returns
        -------
        float
            The damage (1: failure by Miner's rule).

        Raises
        ------
        pdbfs.DataError
            For cycles without a ``range`` or a ``count``, or ranges or
            counts that are negative or not finite.
        """
        ranges, counts = cycles_table(cycles, "SNCurve.damage")
        return float(np.sum(counts / self.cycles_to_failure(ranges)))


GUN_STEEL_SN = SNCurve(m=3.0, stress_range_ref=70e6, cycles_ref=1e6, endurance_limit=0.0)
"""An engineering estimate of the S-N curve of a breech of a high-strength
Cr-Ni-Mo-V gun steel (of the class of ASTM A723), in the range of the bore's
hoop stress, without autofrettage: ``m = 3``, 1e6 cycles at 70 MPa, no
endurance limit. A life governed by the growth of a crack from a small flaw
at the bore: the slope of the steel's Paris law, and about the life
`GUN_STEEL_PARIS` gives a 0.5 mm flaw growing to 20 mm at the bore of
`BREECH_CYLINDER` (5 % shorter, whatever the pressure range). Replace it
with the curve of your steel and detail."""
