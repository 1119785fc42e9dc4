"""Springs (linear, power-law, compression-only) and linear dampers."""
from __future__ import annotations

import casadi as ca

from pdbfs.modelling import Parameter, eq

from ..functions import signed_power
from ..thermal.interfaces import PartialConditionalHeatPort
from .interfaces import PartialCompliant, PartialCompliantWithVelocity


class Spring(PartialCompliant):
    """Spring ``f = k*|e|^n*sign(e)`` on the stretch ``e = s_rel - s_rel0``;
    linear for ``n = 1``. ``compression_only=True`` makes it push, never pull.

    Connectors: ``flange_a`` and ``flange_b``; ``s_rel = flange_b.s - flange_a.s``.

    Parameters
    ----------
    compression_only : bool
        A spring that pushes, never pulls (slack while stretched).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    k = Parameter(1.0, "N/m", "Stiffness (unit N/m^n for an exponent n other than 1)", positive=True)
    n = Parameter(1.0, "1", "Force-law exponent (1: linear)", min=1.0, tunable=False)
    s_rel0 = Parameter(0.0, "m", "Unstretched relative position", tunable=False)

    def __init__(self, compression_only: bool = False, **params: float | ca.SX):
        self._compression_only = compression_only
        super().__init__(**params)

    def equations(self):
        e = self.s_rel - self.s_rel0
        if self._compression_only:
            e = ca.fmin(e, 0.0)
        return super().equations() + [eq(self.f, self.k * signed_power(e, self.n))]

    def events(self):
        return [(self.s_rel - self.s_rel0, "stretch",
                 "the compression-only spring engages or goes slack")] if self._compression_only else []


class Damper(PartialConditionalHeatPort, PartialCompliantWithVelocity):
    """Linear viscous damper ``f = c*v_rel``.

    Connectors: ``flange_a`` and ``flange_b``; ``v_rel`` is flange_b's
    velocity less flange_a's. With ``heat_port=True`` the power it
    dissipates, ``c*v_rel^2``, leaves through ``heat_port``.

    Parameters
    ----------
    heat_port : bool
        Give the damper a heat port that takes its dissipated power.
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    c = Parameter(1.0, "N.s/m", "Damping coefficient", min=0.0)

    def dissipated_power(self):
        return self.f * self.v_rel

    def equations(self):
        return super().equations() + [eq(self.f, self.c * self.v_rel)]
