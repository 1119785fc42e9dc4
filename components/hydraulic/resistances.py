"""Flow resistances between two ports: a turbulent orifice, a laminar leak."""
import casadi as ca

from pdbfs.modelling import Parameter, eq

from ..thermal.interfaces import PartialConditionalHeatPort
from .interfaces import PartialTwoPort
from .laws import regularised_root


class PartialDissipativeTwoPort(PartialConditionalHeatPort, PartialTwoPort):
    """A PartialTwoPort that turns the power of its flow, ``dp*q``, into
    heat: with ``heat_port=True`` it leaves through ``heat_port`` (the oil
    throttled through an orifice, a valve or a leak warms).

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    pressure_bound = {}      # it only dissipates (modelling.pressure_bound)

    def dissipated_power(self):
        return self.dp * self.q


class PartialOrifice(PartialDissipativeTwoPort):
    """Turbulent flow through an opening: ``q = x*Cd*A*sqrt(2/rho)*root(dp)``
    with ``root`` the regularised square root of laws.regularised_root
    (``dp/(dp^2 + dp_t^2)^(1/4)``: slope ``1/sqrt(dp_t)`` at dp = 0 instead
    of infinite; relative error below ``(dp_t/dp)^2/4``, 2.5e-5 of the flow
    at ``|dp| = 100*dp_t``) and ``x`` the opening a subclass gives
    (``opening()``, 1 by default; ``open_fraction()`` where a subclass
    uses the name ``opening`` for something else, as CommandedValve's
    signal input).

    Connectors: ``port_a`` and ``port_b``; the flow ``q`` goes from a to b;
    with ``heat_port=True`` also ``heat_port``, where the power ``dp*q``
    leaves as heat.

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    Cd = Parameter(0.7, "1", "Discharge coefficient", positive=True, max=1.0)
    A = Parameter(1e-5, "m2", "Flow area (fully open)", positive=True)
    rho = Parameter(870.0, "kg/m3", "Density of the oil", positive=True, tunable=False)
    dp_t = Parameter(1e3, "Pa", "Pressure difference below which the square-root law is "
                     "rounded to stay smooth", positive=True, tunable=False)

    def opening(self):
        """The valve's opening x, 0 (closed) to 1 (fully open): 1 for a fixed orifice."""
        return 1.0

    def open_fraction(self):
        """The opening ``x`` the flow law uses (``opening()``)."""
        return self.opening()

    def equations(self):
        return super().equations() + [
            eq(self.q, self.open_fraction() * self.Cd * self.A * ca.sqrt(2.0 / self.rho)
               * regularised_root(self.dp, self.dp_t))]


class Orifice(PartialOrifice):
    """A fixed sharp-edged orifice (turbulent), ports ``port_a``,
    ``port_b``, flow ``q`` from a to b: ``q = Cd*A*sqrt(2/rho)*root(dp)``
    (PartialOrifice's law, fully open).

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """


class LaminarLeak(PartialDissipativeTwoPort):
    """A laminar leak ``q = G*dp`` (a seal gap, a capillary).

    Connectors: ``port_a`` and ``port_b``; the flow ``q`` goes from a to b;
    with ``heat_port=True`` also ``heat_port`` (the power ``dp*q`` as heat).

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    G = Parameter(1e-12, "m3/(s.Pa)", "Hydraulic conductance", min=0.0)

    def equations(self):
        return super().equations() + [eq(self.q, self.G * self.dp)]
