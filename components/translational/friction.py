"""Seal friction between a sliding body and the frame."""
from __future__ import annotations

import casadi as ca

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, Variable, eq

from ..thermal.interfaces import T_ROOM, PartialConditionalHeatPort
from ..thermal.laws import VISCOSITY_LAWS, WATER_GLYCOL_ANDRADE_B
from .interfaces import PartialCompliantWithVelocity


class SealFriction(PartialConditionalHeatPort, PartialCompliantWithVelocity):
    """Friction of a seal: viscous ``c*v_rel`` plus an optional Coulomb part
    ``F_c*tanh(v_rel/v_eps)``, regularised so that it stays smooth:
    ``f = c*v_rel + F_c*tanh(v_rel/v_eps)``. flange_a on the frame, flange_b
    on the sliding body.

    ``heat_port=True``: the power it dissipates, ``f*v_rel``, leaves through
    ``heat_port``. ``viscosity_law="andrade"``: the viscous coefficient
    follows the oil's viscosity, ``c*exp(B*(1/T - 1/T_ref))`` at the
    temperature ``T`` of the heat port (without one, of the parameter
    ``T``), ``c`` holding at ``T_ref``; ``B`` defaults to the paper's
    water-glycol fluid (B = 0: no change). The variable ``c_T`` is the
    coefficient at that temperature.

    Connectors: ``flange_a`` (the frame), ``flange_b`` (the sliding body);
    ``heat_port`` with ``heat_port=True``.

    Parameters
    ----------
    viscosity_law : {None, "andrade"}
        The viscous coefficient's temperature law (adds ``T_ref``, ``B``,
        and ``T`` without a heat port); None: ``c`` is constant.
    heat_port : bool
        Give the seal a heat port that takes its dissipated power.
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown law.
    """

    c = Parameter(2.556e4, "N.s/m", "Viscous friction coefficient; the paper's c2", min=0.0)
    F_c = Parameter(0.0, "N", "Coulomb friction force (0: none)", min=0.0)
    v_eps = Parameter(1e-3, "m/s", "Velocity scale of the Coulomb regularisation",
                      positive=True)

    def __init__(self, viscosity_law: str | None = None, heat_port: bool = False,
                 **params: float | ca.SX):
        if viscosity_law is not None and viscosity_law not in VISCOSITY_LAWS:
            raise ParameterError(f"SealFriction: unknown viscosity law {viscosity_law!r}; "
                                 f"choose one of {', '.join(VISCOSITY_LAWS)}")
        self._law = viscosity_law
        super().__init__(heat_port=heat_port, **params)

    def declare(self):
        super().declare()
        if self._law is not None:
            self.declare_temperature()
            self.T_ref = Parameter(T_ROOM, "K", "Temperature at which c holds", positive=True)
            self.B = Parameter(WATER_GLYCOL_ANDRADE_B, "K", "Andrade's constant of the oil's "
                               "viscosity, ln(mu1/mu2)/(1/T1 - 1/T2) (0: c does not change)",
                               min=0.0)
            self.c_T = Variable("N.s/m", "Viscous friction coefficient at the temperature",
                                output=True)

    def dissipated_power(self):
        return self.f * self.v_rel

    def equations(self):
        eqs = super().equations()
        c = self.c
        if self._law is not None:
            eqs.append(eq(self.c_T, self.c * VISCOSITY_LAWS[self._law](
                self.port_temperature(), self.T_ref, self.B)))
            c = self.c_T
        return eqs + [eq(self.f, c * self.v_rel + self.F_c * ca.tanh(self.v_rel / self.v_eps))]
