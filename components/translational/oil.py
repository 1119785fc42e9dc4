"""The oil column between the loading piston and the breech, as a compression-only spring."""
from __future__ import annotations

from typing import TYPE_CHECKING

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, Variable, eq

from ..functions import positive_power
from ..thermal.interfaces import T_ROOM, PartialConditionalHeatPort
from ..thermal.laws import STIFFNESS_LAWS, WATER_GLYCOL_MODULUS_FALL
from .interfaces import PartialCompression

if TYPE_CHECKING:
    import casadi as ca


class OilColumn(PartialConditionalHeatPort, PartialCompression):
    """A column of oil squeezed by a piston of area ``A``: a compression-only
    spring ``fc = k*max(d, 0)^n`` with ``d = -s_rel`` (flange_a: piston,
    flange_b: the closed end); ``pressure = fc / A``.

    Linear (``n = 1``) by default: the paper's Table 1 prints the unit of k2
    as N/m^1.5, but its Figs. 5, 6 and 9 only fit a linear oil spring (the
    documentation's page on the paper's rig shows why); ``n = 1.5`` gives
    the other reading.

    Give ``k`` directly, or ``bulk_modulus=True`` to compute it as
    ``K*A/L`` from the parameters ``K`` (bulk modulus) and ``L`` (length).

    ``stiffness_law``: the stiffness falls with the oil's bulk modulus as
    the oil warms, ``k*factor(T)`` with ``factor`` ``1 - alpha_T*(T -
    T_ref)`` (``"linear"``) or ``exp(-alpha_T*(T - T_ref))``
    (``"exponential"``), ``k`` holding at ``T_ref``; ``alpha_T`` defaults to
    the paper's water-glycol fluid (0: no change). ``T`` is the temperature
    of ``heat_port`` (``heat_port=True``; the column is lossless, so no heat
    flows there), else the parameter ``T``. The variable ``k_T`` is the
    stiffness at that temperature.

    Connectors: ``flange_a`` (the piston), ``flange_b`` (the closed end);
    ``heat_port`` with ``heat_port=True``.

    Parameters
    ----------
    bulk_modulus : bool
        Compute ``k`` as ``K*A/L`` from the bulk modulus ``K`` and the
        column's length ``L`` (two more parameters).
    stiffness_law : {None, "linear", "exponential"}
        The stiffness's temperature law (adds ``T_ref``, ``alpha_T``, and
        ``T`` without a heat port); None: ``k`` is constant.
    heat_port : bool
        Give the column a heat port, whose temperature the law reads.
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown law.
    """

    heat_port_description = "The oil's temperature (the lossless column passes no heat)"
    k = Parameter(2.228e8, "N/m", "Oil column stiffness (unit N/m^n); the paper's k2",
                  positive=True)
    n = Parameter(1.0, "1", "Force-law exponent: 1 linear (default, fits the paper's "
                  "figures), 1.5 the Hertz-like reading of Table 1's unit", min=1.0,
                  tunable=False)
    A = Parameter(2.270e-2, "m2", "Piston area the pressure acts on", positive=True,
                  tunable=False)

    def __init__(self, bulk_modulus: bool = False, stiffness_law: str | None = None,
                 heat_port: bool = False, **params: float | ca.SX):
        if stiffness_law is not None and stiffness_law not in STIFFNESS_LAWS:
            raise ParameterError(f"OilColumn: unknown stiffness law {stiffness_law!r}; "
                                 f"choose one of {', '.join(STIFFNESS_LAWS)}")
        self._from_bulk = bulk_modulus
        self._law = stiffness_law
        super().__init__(heat_port=heat_port, **params)

    def declare(self):
        super().declare()
        self.pressure = Variable("Pa", "Oil pressure (at the breech)", output=True)
        if self._from_bulk:
            self.K = Parameter(2.2e9, "Pa", "Bulk modulus of the oil", positive=True)
            self.L = Parameter(0.2, "m", "Length of the oil column", positive=True,
                                   tunable=False)
            self.bind("k", self.K * self.A / self.L)
        if self._law is not None:
            self.declare_temperature()
            self.T_ref = Parameter(T_ROOM, "K", "Temperature at which k holds", positive=True)
            self.alpha_T = Parameter(WATER_GLYCOL_MODULUS_FALL, "1/K", "Relative fall of the "
                                     "stiffness (the bulk modulus) per kelvin at T_ref (0: k "
                                     "does not change)", min=0.0)
            self.k_T = Variable("N/m", "Stiffness at the oil's temperature (unit N/m^n)",
                                output=True, min=0.0, beyond="the linear stiffness law reached "
                                "zero (the oil is hotter than T_ref + 1/alpha_T): use "
                                "stiffness_law='exponential'")

    def dissipated_power(self):
        return 0.0

    def equations(self):
        eqs = super().equations()
        k = self.k
        if self._law is not None:
            eqs.append(eq(self.k_T, self.k * STIFFNESS_LAWS[self._law](
                self.port_temperature(), self.T_ref, self.alpha_T)))
            k = self.k_T
        return eqs + [
            eq(self.d, -self.s_rel),
            eq(self.fc, k * positive_power(self.d, self.n)),
            eq(self.pressure * self.A, self.fc)]

    def events(self):
        return [(self.d, "compression", "the oil column engages or goes slack")]
