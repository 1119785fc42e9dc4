"""Small CasADi helpers shared by the compiler's passes."""
from __future__ import annotations

import casadi as ca


def subst(expr, keys, vals):
    """ca.substitute that tolerates structural zeros and empty key lists."""
    if keys.numel() == 0:
        return expr
    return ca.substitute(ca.SX(expr), keys, ca.densify(ca.SX(vals)))
