"""Seal friction between a sliding body and the frame."""
import casadi as ca

from pdbfs.modelling import Parameter, eq

from .interfaces import PartialCompliantWithVelocity


class SealFriction(PartialCompliantWithVelocity):
    """Friction of a seal: viscous ``c*v_rel`` plus an optional Coulomb part
    ``F_c*tanh(v_rel/v_eps)``, regularised so that it stays smooth:
    ``f = c*v_rel + F_c*tanh(v_rel/v_eps)``. flange_a on the frame, flange_b
    on the sliding body."""

    c = Parameter(2.556e4, "N.s/m", "Viscous friction coefficient; the paper's c2", min=0.0)
    F_c = Parameter(0.0, "N", "Coulomb friction force (0: none)", min=0.0)
    v_eps = Parameter(1e-3, "m/s", "Velocity scale of the Coulomb regularisation",
                      positive=True)

    def equations(self):
        return super().equations() + [
            eq(self.f, self.c * self.v_rel + self.F_c * ca.tanh(self.v_rel / self.v_eps))]
