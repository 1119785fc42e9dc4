"""Temperature laws and material data, as plain functions of numbers or
CasADi expressions.

A law gives the factor by which a coefficient known at the reference
temperature ``T_ref`` changes at the temperature ``T`` (both K): a stiffness
falling with the bulk modulus of the oil, a viscous friction coefficient
falling with the oil's viscosity. Each factor is exactly 1 at ``T = T_ref``
and for a zero coefficient, so a law switched off changes nothing.

The material data are the defaults of the thermal rig, for the paper's
water-glycol fluid (an HFC fluid of ISO 6743-4, viscosity grade ISO VG 46)
and for steel; the documentation page on the thermal domain gives their
sources and says which are engineering estimates.
"""
from __future__ import annotations

import math

import casadi as ca

#: steel (low-alloy, as a breech and a loading piston), J/(kg.K) at 20 degC
STEEL_SPECIFIC_HEAT = 460.0
#: water-glycol (HFC, about 40 % water), kg/m3 at 20 degC
WATER_GLYCOL_DENSITY = 1080.0
#: J/(kg.K) at 20 degC (an estimate between water's 4180 and glycols' 2400)
WATER_GLYCOL_SPECIFIC_HEAT = 3300.0
#: Pa at 20 degC and low pressure
WATER_GLYCOL_BULK_MODULUS = 3.4e9
#: relative fall of the bulk modulus per kelvin, 1/K (an engineering estimate)
WATER_GLYCOL_MODULUS_FALL = 4e-3
#: kinematic viscosity of ISO VG 46 at 40 degC (ISO 3448) and, typical of
#: water-glycols' high viscosity index, at 100 degC: (T in K, m2/s)
WATER_GLYCOL_VISCOSITY = ((313.15, 46e-6), (373.15, 9e-6))


def linear_factor(T: float | ca.SX, T_ref: float | ca.SX, alpha: float | ca.SX
                  ) -> float | ca.SX:
    """``1 - alpha*(T - T_ref)``: a coefficient falling by the fraction
    ``alpha`` (1/K) of its value at ``T_ref`` per kelvin. It reaches zero at
    ``T_ref + 1/alpha``: use it over a few tens of kelvin.

    Parameters
    ----------
    T : float or casadi.SX
        The temperature, K.
    T_ref : float or casadi.SX
        The temperature at which the coefficient holds, K.
    alpha : float or casadi.SX
        The relative fall per kelvin, 1/K (0: no change).

    Returns
    -------
    float or casadi.SX
        The factor on the coefficient, 1 at ``T_ref``.
    """
    return 1.0 - alpha * (T - T_ref)


def exponential_factor(T: float | ca.SX, T_ref: float | ca.SX, alpha: float | ca.SX
                       ) -> float | ca.SX:
    """``exp(-alpha*(T - T_ref))``: a coefficient falling by the fraction
    ``alpha`` (1/K) of its current value per kelvin; the same slope as
    linear_factor at ``T_ref``, and never zero.

    Parameters
    ----------
    T : float or casadi.SX
        The temperature, K.
    T_ref : float or casadi.SX
        The temperature at which the coefficient holds, K.
    alpha : float or casadi.SX
        The relative fall per kelvin, 1/K (0: no change).

    Returns
    -------
    float or casadi.SX
        The factor on the coefficient, 1 at ``T_ref``.
    """
    return ca.exp(-alpha * (T - T_ref)) if _symbolic(T, T_ref, alpha) \
        else math.exp(-alpha * (T - T_ref))


def andrade_factor(T: float | ca.SX, T_ref: float | ca.SX, B: float | ca.SX) -> float | ca.SX:
    """Andrade's law of a liquid's viscosity, ``exp(B*(1/T - 1/T_ref))``: the
    viscosity at ``T`` over that at ``T_ref`` (the relative fall per kelvin
    is ``B/T**2``).

    Parameters
    ----------
    T : float or casadi.SX
        The temperature, K.
    T_ref : float or casadi.SX
        The temperature of the reference viscosity, K.
    B : float or casadi.SX
        Andrade's constant of the liquid, K (``andrade_constant``; 0: no change).

    Returns
    -------
    float or casadi.SX
        The factor on the viscosity, 1 at ``T_ref``.
    """
    x = B * (1.0 / T - 1.0 / T_ref)
    return ca.exp(x) if _symbolic(T, T_ref, B) else math.exp(x)


def andrade_constant(T1: float, nu1: float, T2: float, nu2: float) -> float:
    """Andrade's constant ``B`` through two points of a viscosity curve, as a
    fluid's data sheet gives them at 40 and 100 degC.

    Parameters
    ----------
    T1, T2 : float
        The two temperatures, K (> 0, different).
    nu1, nu2 : float
        The viscosities there (> 0, in any one unit).

    Returns
    -------
    float
        ``B``, K.

    Raises
    ------
    ValueError
        For a value that is not > 0, or equal temperatures.

    Examples
    --------
    ISO VG 46 water-glycol, 46 mm2/s at 40 degC and 9 mm2/s at 100 degC:

    >>> from pdbfs.components.thermal import andrade_constant
    >>> f"{andrade_constant(313.15, 46e-6, 373.15, 9e-6):.4g} K"
    '3177 K'
    """
    for name, v in (("T1", T1), ("T2", T2), ("nu1", nu1), ("nu2", nu2)):
        if not v > 0:
            raise ValueError(f"andrade_constant: {name} = {v} must be > 0")
    if T1 == T2:
        raise ValueError("andrade_constant: T1 and T2 must differ")
    return math.log(nu1 / nu2) / (1.0 / T1 - 1.0 / T2)


#: the oil column's stiffness laws (OilColumn(stiffness_law=...))
STIFFNESS_LAWS = {"linear": linear_factor, "exponential": exponential_factor}
#: the viscous friction laws (SealFriction(viscosity_law=...))
VISCOSITY_LAWS = {"andrade": andrade_factor}
#: Andrade's B of the water-glycol fluid, K (about 3180 K: the viscosity falls
#: by 3.7 % per kelvin at 20 degC, 3.2 % at 40 degC)
WATER_GLYCOL_ANDRADE_B = andrade_constant(*WATER_GLYCOL_VISCOSITY[0], *WATER_GLYCOL_VISCOSITY[1])


def _symbolic(*xs) -> bool:
    return any(isinstance(x, (ca.SX, ca.MX)) for x in xs)
