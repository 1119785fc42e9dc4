"""Contact laws of the paper, as plain functions (numbers or CasADi expressions).

References: Hertz stiffness of two spheres (paper eq. 2-3), damping factors
of Lankarani & Nikravesh (paper eq. 6), Hunt & Crossley, Flores et al.;
(restitution estimated from a force history after Guo & Batzer, paper eq. 8,
is post-processing: pdbfs.simulation.results.impulse).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import casadi as ca

STANDARD_GRAVITY = 9.80665   # m/s^2


def hertz_stiffness(E1: float, nu1: float, R1: float, E2: float, nu2: float, R2: float) -> float:
    """Hertz contact stiffness of two spheres (the paper's eq. 2-3):
    ``k = 4/3 * E* * sqrt(R*)``, ``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2``,
    ``1/R* = 1/R1 + 1/R2``.

    Parameters
    ----------
    E1, E2 : float
        Young's moduli of the two bodies, Pa (> 0).
    nu1, nu2 : float
        Their Poisson ratios, in [0, 0.5).
    R1, R2 : float
        Their radii of curvature at the contact, m (> 0; a flat face has
        ``R = inf``).

    Returns
    -------
    float
        The stiffness k of ``f = k d^1.5``, N/m^1.5.

    Raises
    ------
    ValueError
        For a modulus or radius that is not > 0, or a Poisson ratio out of range.

    Examples
    --------
    A steel sphere of radius 0.5 m on a flat steel face:

    >>> from pdbfs.components import hertz_stiffness
    >>> f"{hertz_stiffness(210e9, 0.3, 0.5, 210e9, 0.3, float('inf')):.3g} N/m^1.5"
    '1.09e+11 N/m^1.5'
    """
    for name, v in (("E1", E1), ("E2", E2), ("R1", R1), ("R2", R2)):
        if not v > 0:
            raise ValueError(f"hertz_stiffness: {name} = {v} must be > 0")
    for name, v in (("nu1", nu1), ("nu2", nu2)):
        if not 0 <= v < 0.5:
            raise ValueError(f"hertz_stiffness: Poisson ratio {name} = {v} must be in [0, 0.5)")
    e_star = 1.0 / ((1 - nu1 ** 2) / E1 + (1 - nu2 ** 2) / E2)
    r_star = 1.0 / (1.0 / R1 + 1.0 / R2)
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


def damping_lankarani_nikravesh(k: float | ca.SX, e: float | ca.SX, v_impact: float | ca.SX
                                ) -> float | ca.SX:
    """Lankarani & Nikravesh's hysteresis damping factor (the paper's eq. 6),
    ``D = 3 k (1 - e^2) / (4 v)``.

    Parameters
    ----------
    k : float or casadi.SX
        The contact stiffness, N/m^n.
    e : float or casadi.SX
        The coefficient of restitution, in (0, 1].
    v_impact : float or casadi.SX
        The impact speed, m/s (> 0).

    Returns
    -------
    float or casadi.SX
        The damping factor D of ``f = k d^n + D d^n dd/dt``, N.s/m^(n+1).
    """
    return 3.0 * k * (1.0 - e ** 2) / (4.0 * v_impact)


def damping_hunt_crossley(k: float | ca.SX, e: float | ca.SX, v_impact: float | ca.SX
                          ) -> float | ca.SX:
    """Hunt & Crossley's hysteresis damping factor, ``D = 3 k (1 - e) / (2 v)``.

    Parameters
    ----------
    k : float or casadi.SX
        The contact stiffness, N/m^n.
    e : float or casadi.SX
        The coefficient of restitution, in (0, 1].
    v_impact : float or casadi.SX
        The impact speed, m/s (> 0).

    Returns
    -------
    float or casadi.SX
        The damping factor D, N.s/m^(n+1).
    """
    return 3.0 * k * (1.0 - e) / (2.0 * v_impact)


def damping_flores(k: float | ca.SX, e: float | ca.SX, v_impact: float | ca.SX) -> float | ca.SX:
    """Flores et al.'s hysteresis damping factor, ``D = 8 k (1 - e) / (5 e v)``
    (for low restitution too).

    Parameters
    ----------
    k : float or casadi.SX
        The contact stiffness, N/m^n.
    e : float or casadi.SX
        The coefficient of restitution, in (0, 1].
    v_impact : float or casadi.SX
        The impact speed, m/s (> 0).

    Returns
    -------
    float or casadi.SX
        The damping factor D, N.s/m^(n+1).
    """
    return 8.0 * k * (1.0 - e) / (5.0 * e * v_impact)


DAMPING_LAWS = {
    "lankarani-nikravesh": damping_lankarani_nikravesh,
    "hunt-crossley": damping_hunt_crossley,
    "flores": damping_flores,
}


def impact_velocity(h: float, g: float = STANDARD_GRAVITY) -> float:
    """Speed after a free fall, ``sqrt(2 g h)``.

    Parameters
    ----------
    h : float
        The drop height, m (>= 0).
    g : float
        The acceleration of gravity, m/s^2 (default: standard gravity).

    Returns
    -------
    float
        The impact speed, m/s.

    Raises
    ------
    ValueError
        For a negative height.

    Examples
    --------
    >>> from pdbfs.components import impact_velocity
    >>> f"{impact_velocity(0.38):.3g} m/s"
    '2.73 m/s'
    """
    if not h >= 0:
        raise ValueError(f"impact_velocity: drop height h = {h} must be >= 0")
    return math.sqrt(2.0 * g * h)
