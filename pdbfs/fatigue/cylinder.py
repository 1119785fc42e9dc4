"""Lamé's stresses in a thick-walled cylinder under internal pressure: the
breech's wall, whose largest stress, the hoop stress at the bore, is what
its fatigue life is read from."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from pdbfs.errors import ParameterError

from .checks import positive


@dataclass(frozen=True)
class ThickCylinder:
    """A thick-walled cylinder (Lamé), pressurised inside, free outside.

    Parameters
    ----------
    inner_radius : float
        The bore's radius, m (> 0).
    outer_radius : float
        The outer radius, m (above ``inner_radius``).

    Raises
    ------
    pdbfs.ParameterError
        For a radius that is not a positive finite number, or an outer
        radius not above the inner one.

    Examples
    --------
    A wall of radius ratio 2: the bore's hoop stress is 5/3 of the pressure.

    >>> from pdbfs.fatigue import ThickCylinder
    >>> round(ThickCylinder(0.08, 0.16).bore_hoop_stress(300e6) / 300e6, 12)
    1.666666666667
    """

    inner_radius: float
    outer_radius: float

    def __post_init__(self):
        a = positive(self.inner_radius, "inner_radius", "ThickCylinder")
        b = positive(self.outer_radius, "outer_radius", "ThickCylinder")
        if b <= a:
            raise ParameterError(f"ThickCylinder: outer_radius = {b:g} m must be above "
                                 f"inner_radius = {a:g} m")
        object.__setattr__(self, "inner_radius", a)
        object.__setattr__(self, "outer_radius", b)

    @property
    def wall_thickness(self) -> float:
        """The wall's thickness, m."""
        return self.outer_radius - self.inner_radius

    @property
    def bore_factor(self) -> float:
        """The bore's hoop stress per unit pressure, ``(b^2 + a^2) / (b^2 - a^2)``."""
        a2, b2 = self.inner_radius ** 2, self.outer_radius ** 2
        return (b2 + a2) / (b2 - a2)

    def hoop_stress(self, p: Any, r: float) -> float | np.ndarray:
        """The hoop stress at radius ``r`` under the internal pressure ``p``,
        ``p a^2 / (b^2 - a^2) * (1 + b^2 / r^2)``.

        Parameters
        ----------
        p : float or array_like
            Internal pressure, Pa.
        r : float
            Radius, m, in the wall (from the inner to the outer radius).

        Returns
        -------
        float or numpy.ndarray
            The hoop stress, Pa (tensile positive), of the shape of ``p``.

        Raises
        ------
        pdbfs.ParameterError
            For a radius outside the wall.
        """
        r = positive(r, "r", "ThickCylinder.hoop_stress")
        a, b = self.inner_radius, self.outer_radius
        if not a * (1 - 1e-12) <= r <= b * (1 + 1e-12):
            raise ParameterError(f"ThickCylinder.hoop_stress: r = {r:g} m is outside the wall "
                                 f"({a:g} to {b:g} m)")
        s = np.asarray(p, dtype=float) * a * a / (b * b - a * a) * (1.0 + b * b / (r * r))
        return float(s) if s.ndim == 0 else s

    def bore_hoop_stress(self, p: Any) -> float | np.ndarray:
        """The hoop stress at the bore under the internal pressure ``p``,
        ``p (b^2 + a^2) / (b^2 - a^2)``: the wall's largest stress.

        Parameters
        ----------
        p : float or array_like
            Internal pressure, Pa.

        Returns
        -------
        float or numpy.ndarray
            The bore's hoop stress, Pa, of the shape of ``p``.
        """
        s = np.asarray(p, dtype=float) * self.bore_factor
        return float(s) if s.ndim == 0 else s
