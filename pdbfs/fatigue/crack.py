"""The growth of a radial crack at the bore by Paris' law, as the
cannon-fatigue literature reckons a breech's life: the crack opened by the
bore's hoop stress and by the pressure on its own faces, grown from an
initial flaw to a final depth, cycle by cycle."""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from pdbfs.errors import ParameterError

from .checks import cycles_table, positive
from .cylinder import ThickCylinder

#: points at which a geometry function Y(a / W) is checked before the integration
Y_CHECKS = 33


@dataclass(frozen=True)
class ParisLaw:
    """Paris' law of crack growth, ``da/dN = C * dK**m`` (no threshold: every
    cycle grows the crack).

    Parameters
    ----------
    C : float
        The coefficient, in m per cycle at a stress intensity range of
        1 Pa*sqrt(m) (SI: m/cycle / (Pa*sqrt(m))^m; > 0). A coefficient
        given for dK in MPa*sqrt(m) is ``C_MPa * 1e-6**m`` in SI.
    m : float
        The exponent (> 0).

    Raises
    ------
    pdbfs.ParameterError
        For a value that is not a positive finite number.

    Examples
    --------
    >>> from pdbfs.fatigue import ParisLaw
    >>> law = ParisLaw(C=6.52e-12 * 1e-6 ** 3, m=3.0)   # 6.52e-12 m/cycle at 1 MPa*sqrt(m)
    >>> round(law.rate(20e6), 12)                        # at 20 MPa*sqrt(m): m per cycle
    5.216e-08
    """

    C: float
    m: float

    def __post_init__(self):
        object.__setattr__(self, "C", positive(self.C, "C", "ParisLaw"))
        object.__setattr__(self, "m", positive(self.m, "m", "ParisLaw"))

    def rate(self, delta_K: Any) -> float | np.ndarray:
        """The crack's growth per cycle at a stress intensity range.

        Parameters
        ----------
        delta_K : float or array_like
            Stress intensity factor range, Pa*sqrt(m) (0 or more).

        Returns
        -------
        float or numpy.ndarray
            da/dN, m per cycle.
        """
        k = np.asarray(delta_K, dtype=float)
        r = self.C * k ** self.m
        return float(r) if r.ndim == 0 else r


GUN_STEEL_PARIS = ParisLaw(C=6.52e-12 * 1e-6 ** 3, m=3.0)
"""Paris' law of a high-strength Cr-Ni-Mo-V gun steel (of the class of ASTM
A723) as the cannon-fatigue literature gives it: 6.52e-12 m per cycle at
1 MPa*sqrt(m), ``m = 3`` (``C`` = 6.52e-30 in SI). An engineering estimate:
use your steel's own."""


def crack_growth_cycles(cylinder: ThickCylinder, law: ParisLaw, pressure_range: float,
                        a0: float, af: float, Y: float | Callable[[float], float] = 1.12,
                        crack_face_pressure: bool = True) -> float:
    """The cycles of a constant pressure range that grow a radial crack at
    the bore from ``a0`` to ``af``.

    The crack's stress intensity range is ``dK = Y * (ds + dp) * sqrt(pi*a)``
    with ``ds`` the bore's hoop stress range (Lamé, of the uncracked wall)
    and ``dp`` the pressure range on the crack's faces (left out with
    ``crack_face_pressure=False``); ``N = integral of da / (C dK^m)`` from
    a0 to af, integrated numerically (to a relative 1e-10) whatever Y is.

    Parameters
    ----------
    cylinder : ThickCylinder
        The breech's wall.
    law : ParisLaw
        The steel's crack growth.
    pressure_range : float
        The pressure range of a cycle, Pa (> 0).
    a0, af : float
        The initial and final crack depths, m (0 < a0 < af < the wall's thickness).
    Y : float or callable, optional
        The geometry factor: a number (default 1.12, an edge crack), or a
        function of the depth over the wall's thickness, ``Y(a / W)``.
    crack_face_pressure : bool, optional
        Whether the pressure also acts on the crack's faces (default True:
        the fluid enters the crack).

    Returns
    -------
    float
        The cycles, of that pressure range, from ``a0`` to ``af``.

    Raises
    ------
    pdbfs.ParameterError
        For a range or depth out of its range, or a geometry factor that is
        not a positive finite number (at some depth, for a function).

    Examples
    --------
    >>> from pdbfs.fatigue import GUN_STEEL_PARIS, ThickCylinder, crack_growth_cycles
    >>> n = crack_growth_cycles(ThickCylinder(0.08, 0.16), GUN_STEEL_PARIS, 100e6,
    ...                         a0=0.5e-3, af=0.02)
    >>> round(n, -2)
    77900.0
    """
    from scipy.integrate import quad
    owner = "crack_growth_cycles"
    if not isinstance(cylinder, ThickCylinder) or not isinstance(law, ParisLaw):
        raise ParameterError(f"{owner}: give a ThickCylinder and a ParisLaw, not "
                             f"{type(cylinder).__name__} and {type(law).__name__}")
    dp = positive(pressure_range, "pressure_range", owner)
    a0 = positive(a0, "a0", owner)
    af = positive(af, "af", owner)
    w = cylinder.wall_thickness
    if not a0 < af < w:
        raise ParameterError(f"{owner}: the depths must be 0 < a0 < af < the wall's thickness "
                             f"{w:g} m; a0 = {a0:g} m, af = {af:g} m")
    ds = cylinder.bore_hoop_stress(dp) + (dp if crack_face_pressure else 0.0)
    y = _geometry(Y, a0 / w, af / w, owner)
    scale = law.C * (ds * math.sqrt(math.pi)) ** law.m

    def per_log_depth(u):                     # dN / d(ln a) = a / (C dK^m)
        a = math.exp(u)
        return a / (scale * (y(a / w) * math.sqrt(a)) ** law.m)

    n, _ = quad(per_log_depth, math.log(a0), math.log(af), epsabs=0.0, epsrel=1e-10, limit=200)
    return float(n)


def _geometry(Y, lo: float, hi: float, owner: str) -> Callable[[float], float]:
    """The geometry factor as a function of a / W, checked positive and
    finite over [lo, hi]."""
    if not callable(Y):
        y = positive(Y, "Y", owner)
        return lambda r: y
    for r in np.linspace(lo, hi, Y_CHECKS):
        try:
            v = float(Y(float(r)))
        except (TypeError, ValueError, ArithmeticError) as err:
            raise ParameterError(f"{owner}: Y(a / W) fails at a / W = {r:.4g} ({err})") from None
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(f"{owner}: Y(a / W) = {v:g} at a / W = {r:.4g}; a geometry "
                                 "factor must be a positive finite number")
    return lambda r: float(Y(r))


def equivalent_range(cycles: Any, m: float) -> float:
    """The constant range that does, cycle for cycle, what counted cycles do
    under a power law of exponent ``m``: ``(sum(count * range^m) / sum(count))^(1/m)``.

    Under Paris' law with dK proportional to the pressure (as in
    :func:`crack_growth_cycles`), a history repeated grows the crack as
    ``sum(count)`` cycles of this range do: the histories from a0 to af are
    ``crack_growth_cycles(..., equivalent_range(cycles, law.m), ...) / sum(count)``.

    Parameters
    ----------
    cycles : pandas.DataFrame or mapping
        Counted cycles with columns ``range`` and ``count`` (as rainflow() gives them).
    m : float
        The exponent (> 0): Paris' or Basquin's.

    Returns
    -------
    float
        The equivalent range, in the unit of the ranges (0 for no cycles).

    Raises
    ------
    pdbfs.DataError
        For cycles without a ``range`` or a ``count``, or values that are
        negative or not finite.
    """
    m = positive(m, "m", "equivalent_range")
    ranges, counts = cycles_table(cycles, "equivalent_range")
    total = float(np.sum(counts))
    if total == 0:
        return 0.0
    return float((np.sum(counts * ranges ** m) / total) ** (1.0 / m))
