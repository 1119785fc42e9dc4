"""Force laws' building blocks, written so that their derivatives stay
finite everywhere: with a symbolic exponent, ``max(x, 0)**n`` has
d/dn = x**n * log(x), which is 0 * -inf = NaN at x = 0 and would poison
parameter sensitivities; the branches below are never evaluated there."""
import casadi as ca


def positive_power(x, n):
    """``x**n`` for x > 0, else 0 (contact and compression-only laws)."""
    return ca.if_else(x > 0, ca.fmax(x, 0.0) ** n, 0.0)


def signed_power(x, n):
    """``sign(x) * |x|**n`` (symmetric power-law springs). At x = 0 the value
    is 0 and the slope that of the law: 1 for a linear law (n = 1), else 0,
    so that Newton and stiffness estimates see a linear spring at rest."""
    return ca.if_else(x > 0, ca.fmax(x, 0.0) ** n,
                      ca.if_else(x < 0, -(ca.fmax(-x, 0.0) ** n), x * (n == 1)))
