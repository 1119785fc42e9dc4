
from pdbfs.modelling import Parameter, Variable, eq

from ..functions import positive_power
from .interfaces import PartialCompression


class OilColumn(PartialCompression):
    """A column of oil squeezed by a piston of area ``A``: a compression-only
    spring ``fc = k*max(d, 0)^n`` with ``d = -s_rel`` (flange_a: piston,
    flange_b: the closed end); ``pressure = fc / A``.

    Linear (``n = 1``) by default: the paper's Table 1 prints the unit of k2
    as N/m^1.5, but its Figs. 5, 6 and 9 only fit a linear oil spring (see
    docs/explanation/paper-rig.md); ``n = 1.5`` gives the other reading.

    Give ``k`` directly, or ``bulk_modulus=True`` to compute it as
    ``K*A/L`` from the parameters ``K`` (bulk modulus) and ``L`` (length).
    """

    k = Parameter(2.228e8, "N/m", "Oil column stiffness (unit N/m^n); the paper's k2",
                  positive=True)
    n = Parameter(1.0, "1", "Force-law exponent: 1 linear (default, fits the paper's "
                  "figures), 1.5 the Hertz-like reading of Table 1's unit", min=1.0,
                  tunable=False)
    A = Parameter(2.270e-2, "m2", "Piston area the pressure acts on", positive=True,
                  tunable=False)

    def __init__(self, bulk_modulus: bool = False, **params):
        self._from_bulk = bulk_modulus
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.pressure = Variable("Pa", "Oil pressure (at the breech)", output=True)
        if self._from_bulk:
            self.K = Parameter(2.2e9, "Pa", "Bulk modulus of the oil", positive=True)
            self.L = Parameter(0.2, "m", "Length of the oil column", positive=True,
                                   tunable=False)
            self.bind("k", self.K * self.A / self.L)

    def equations(self):
        return super().equations() + [
            eq(self.d, -self.s_rel),
            eq(self.fc, self.k * positive_power(self.d, self.n)),
            eq(self.pressure * self.A, self.fc)]

    def events(self):
        return [(self.d, "compression", "the oil column engages or goes slack")]
