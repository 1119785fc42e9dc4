"""Hydraulic laws as plain functions of numbers or CasADi expressions:
bulk modulus laws, the regularised square root of turbulent orifices, and
the smooth clamp and opening ramp used for cavitation and valves.

Each is written so that its value and first derivative stay finite
everywhere (no 0/0, no infinite slope at dp = 0), so Newton iterations and
Jacobians never see NaN."""
import casadi as ca

ATMOSPHERE = 101325.0   # Pa


def bulk_modulus_constant(p, K):
    """Constant tangent bulk modulus ``K`` (Pa)."""
    return K + 0.0 * p


def bulk_modulus_linear(p, K, K1):
    """Tangent bulk modulus growing linearly with pressure, ``K + K1*p``
    (``K1`` dimensionless; about 5 to 11 for mineral oils, so that K grows by
    half between 0 and 100 MPa for K1 = 7.5 and K = 1.5 GPa)."""
    return K + K1 * p


def bulk_modulus_air(p, K, alpha, n, p_ref, p_min=1e3):
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
    ``p`` is taken no lower than ``p_min`` (1 kPa), where the law would
    divide by zero."""
    pe = ca.fmax(p, p_min)
    r = (p_ref / pe) ** (1.0 / n)
    return K * (1.0 + alpha * r) / (1.0 + alpha * r * K / (n * pe))


def regularised_root(dp, dp_t):
    """``sign(dp)*sqrt(|dp|)`` made smooth at 0: ``dp / (dp^2 + dp_t^2)^(1/4)``.

    Its slope at 0 is ``1/sqrt(dp_t)`` (finite), and it is odd and
    monotonic. Against the true root its relative error is
    ``1 - (1 + (dp_t/dp)^2)^(-1/4)``, below ``(dp_t/dp)^2/4``: 2.5e-5 at
    ``|dp| = 100*dp_t``, 0.16 at ``|dp| = dp_t``."""
    return dp / (dp * dp + dp_t * dp_t) ** 0.25


def smooth_ramp(x, w):
    """``max(x, 0)`` rounded over ``|x| < w`` by a parabola: exactly ``x`` for
    ``x >= w``, exactly 0 for ``x <= -w``, ``(x + w)^2/(4 w)`` in between
    (continuous slope; never negative; at most ``w/4`` above ``max(x, 0)``).
    ``w = 0`` gives the sharp ``max(x, 0)``."""
    ws = ca.fmax(w, 1e-300)
    inner = (x + w) ** 2 / (4.0 * ws)
    return ca.if_else(x >= w, x, ca.if_else(x <= -w, 0.0, inner))


def smooth_step(x):
    """0 for ``x <= 0``, 1 for ``x >= 1``, ``3x^2 - 2x^3`` in between
    (continuous slope): the opening of a valve over its travel."""
    y = ca.fmin(ca.fmax(x, 0.0), 1.0)
    return y * y * (3.0 - 2.0 * y)
