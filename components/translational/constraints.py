"""Ideal kinematic constraints between two flanges: no mass, no compliance,
no loss. They tie positions by a relation that alias elimination cannot
remove, so a rig with one is a high-index DAE that the compiler reduces
(Pantelides' algorithm with dummy derivatives)."""
from pdbfs.modelling import Parameter, eq

from .interfaces import PartialTwoFlanges


class Cam(PartialTwoFlanges):
    """A cam (or a lever of varying ratio): ``flange_b.s = a*s + b*s^2`` with
    ``s = flange_a.s``. It stores no energy: the forces do equal and opposite
    power, ``flange_a.f + (a + 2*b*s)*flange_b.f = 0``. At a dead point
    (``a + 2*b*s = 0``) the constraint cannot be solved for flange_a's body."""

    a = Parameter(1.0, "1", "Linear ratio d(flange_b.s)/d(flange_a.s) at s = 0", tunable=False)
    b = Parameter(0.0, "1/m", "Quadratic coefficient of the cam profile", tunable=False)

    def equations(self):
        s = self.flange_a.s
        return [eq(self.flange_b.s, self.a * s + self.b * s ** 2),
                eq(self.flange_a.f + (self.a + 2 * self.b * s) * self.flange_b.f, 0)]
