"""Hydraulic laws as plain functions of numbers or CasADi expressions:
bulk modulus laws, the regularised square root of turbulent orifices, and
the smooth clamp and opening ramp used for cavitation and valves.

Each is written so that its value and first derivative stay finite
everywhere (no 0/0, no infinite slope at dp = 0), so Newton iterations and
Jacobians never see NaN."""
from __future__ import annotations

import casadi as ca

ATMOSPHERE = 101325.0   # Pa


def bulk_modulus_constant(p: float | ca.SX, K: float | ca.SX) -> float | ca.SX:
    """Constant tangent bulk modulus.

    Parameters
    ----------
    p : float or casadi.SX
        Pressure, Pa (not used: the modulus does not change with it).
    K : float or casadi.SX
        The bulk modulus, Pa.

    Returns
    -------
    float or casadi.SX
        ``K``, Pa.
    """
    return K + 0.0 * p


def bulk_modulus_linear(p: float | ca.SX, K: float | ca.SX, K1: float | ca.SX) -> float | ca.SX:
    """Tangent bulk modulus growing linearly with pressure, ``K + K1*p``.

    Parameters
    ----------
    p : float or casadi.SX
        Pressure, Pa.
    K : float or casadi.SX
        The bulk modulus at zero pressure, Pa.
    K1 : float or casadi.SX
        Its growth with pressure, dimensionless: about 5 to 11 for mineral
        oils (K grows by half between 0 and 100 MPa for K1 = 7.5 and K =
        1.5 GPa).

    Returns
    -------
    float or casadi.SX
        The tangent bulk modulus, Pa.
    """
    return K + K1 * p


def bulk_modulus_air(p: float | ca.SX, K: float | ca.SX, alpha: float | ca.SX, n: float | ca.SX,
                     p_ref: float | ca.SX, p_min: float = 1e3) -> ca.SX:
    """Effective tangent bulk modulus of oil with entrained (undissolved) air.

    The oil (bulk modulus ``K``) holds air bubbles whose volume is the
    fraction ``alpha`` of the liquid volume at the pressure ``p_ref``; the air
    is compressed polytropically (exponent ``n``: 1 isothermal, 1.4
    adiabatic), so its volume scales with ``r = (p_ref/p)**(1/n)``. The
    mixture's ``-V dp/dV`` is

        K_eff = K * (1 + alpha*r) / (1 + alpha*r*K/(n*p))

    which is the entrained-air model of Merritt (Hydraulic Control Systems,
    Wiley 1967, section 2.5) in the form compared by Gholizadeh, Burton and
    Schoenau, "Fluid bulk modulus: comparison of low pressure models",
    International Journal of Fluid Power 13(1), 7-16 (2012), where the
    liquid's own change of volume is neglected beside that of the air. At
    high pressure it tends to ``K``; at low pressure the air dominates.

    Parameters
    ----------
    p : float or casadi.SX
        Pressure, Pa (absolute); taken no lower than ``p_min``, where the
        law would divide by zero.
    K : float or casadi.SX
        The oil's own bulk modulus, Pa.
    alpha : float or casadi.SX
        The air's volume fraction of the liquid volume at ``p_ref``.
    n : float or casadi.SX
        The air's polytropic exponent (1 isothermal, 1.4 adiabatic).
    p_ref : float or casadi.SX
        The pressure at which the fraction is ``alpha``, Pa.
    p_min : float
        The lowest pressure the law is evaluated at, Pa.

    Returns
    -------
    casadi.SX
        The effective tangent bulk modulus, Pa.
    """
    pe = ca.fmax(p, p_min)
    r = (p_ref / pe) ** (1.0 / n)
    return K * (1.0 + alpha * r) / (1.0 + alpha * r * K / (n * pe))


def regularised_root(dp: float | ca.SX, dp_t: float | ca.SX) -> float | ca.SX:
    """``sign(dp)*sqrt(|dp|)`` made smooth at 0: ``dp / (dp^2 + dp_t^2)^(1/4)``.

    Its slope at 0 is ``1/sqrt(dp_t)`` (finite), and it is odd and
    monotonic. Against the true root its relative error is
    ``1 - (1 + (dp_t/dp)^2)^(-1/4)``, below ``(dp_t/dp)^2/4``: 2.5e-5 at
    ``|dp| = 100*dp_t``, 0.16 at ``|dp| = dp_t``.

    Parameters
    ----------
    dp : float or casadi.SX
        The pressure drop, Pa.
    dp_t : float or casadi.SX
        The transition pressure drop, Pa (> 0), below which the root is rounded.

    Returns
    -------
    float or casadi.SX
        The regularised root, Pa^(1/2).
    """
    return dp / (dp * dp + dp_t * dp_t) ** 0.25


def smooth_ramp(x: float | ca.SX, w: float | ca.SX) -> ca.SX:
    """``max(x, 0)`` rounded over ``|x| < w`` by a parabola: exactly ``x`` for
    ``x >= w``, exactly 0 for ``x <= -w``, ``(x + w)^2/(4 w)`` in between
    (continuous slope; never negative; at most ``w/4`` above ``max(x, 0)``).

    Parameters
    ----------
    x : float or casadi.SX
        The value clamped.
    w : float or casadi.SX
        The half-width of the rounding, in x's unit (0: the sharp ``max(x, 0)``).

    Returns
    -------
    casadi.SX
        The clamped value.
    """
    ws = ca.fmax(w, 1e-300)
    inner = (x + w) ** 2 / (4.0 * ws)
    return ca.if_else(x >= w, x, ca.if_else(x <= -w, 0.0, inner))


def smooth_step(x: float | ca.SX) -> ca.SX:
    """0 for ``x <= 0``, 1 for ``x >= 1``, ``3x^2 - 2x^3`` in between
    (continuous slope): the opening of a valve over its travel.

    Parameters
    ----------
    x : float or casadi.SX
        The travel, 0 (closed) to 1 (open).

    Returns
    -------
    casadi.SX
        The opening, 0 to 1.
    """
    y = ca.fmin(ca.fmax(x, 0.0), 1.0)
    return y * y * (3.0 - 2.0 * y)
