"""A gas-charged accumulator."""
from pdbfs.modelling import Parameter, State, Variable, der, eq

from .interfaces import PartialOnePort
from .laws import ATMOSPHERE


class Accumulator(PartialOnePort):
    """A gas-charged (bladder or piston) accumulator: gas of volume ``V0``
    at the precharge pressure ``p_pre`` when empty, compressed
    polytropically by the oil it takes in:

        p * (V0 - V_oil)^n = p_pre * V0^n,   der(V_oil) = port.q

    It starts at pressure ``p0`` (holding ``V0*(1 - (p_pre/p0)^(1/n))`` of
    oil). The oil is taken as incompressible beside the gas. Drawn below
    empty (``V_oil < 0``, ``p < p_pre``) the gas law is continued (a real
    bladder would close its poppet): watch ``V_oil``; a start below the
    precharge (``p0 < p_pre``) is refused.

    ``steady_start=True``: in equilibrium with its line at the start (no oil
    flows in, ``der(V_oil) = 0``); the oil it holds is then solved at
    initialization and ``p0`` is only a guess (the line behind a
    resistance, e.g. a Volume, must fix the pressure).

    Connector: ``port`` (closable).

    Parameters
    ----------
    steady_start : bool
        Start in equilibrium with its line (the oil held solved, ``p0`` a guess).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    pressure_bound = {"stores": ("p",)}    # its start pressure (modelling.pressure_bound)

    closable = True
    V0 = Parameter(1e-3, "m3", "Gas volume at precharge (the accumulator's size)",
                   positive=True, tunable=False)
    p_pre = Parameter(5e6, "Pa", "Gas precharge pressure (absolute)", positive=True,
                      tunable=False)
    p0 = Parameter(20e6, "Pa", "Start pressure (absolute)", positive=True, tunable=False)
    n = Parameter(1.4, "1", "Polytropic exponent of the gas (1 isothermal, 1.4 adiabatic)",
                  min=1.0, max=1.67, tunable=False)

    def __init__(self, steady_start: bool = False, **params):
        self._steady_start = bool(steady_start)
        super().__init__(**params)

    def declare(self):
        super().declare()
        self.V_oil = State("m3", "Oil volume held",
                           start=self.V0 * (1.0 - (self.p_pre / self.p0) ** (1.0 / self.n)),
                           fixed=not self._steady_start)
        self.p = Variable("Pa", "Gas and oil pressure (absolute)", output=True)

    def initial_equations(self):
        return [der(self.V_oil)] if self._steady_start else []

    def conditions(self):
        return [(self.p0 - self.p_pre, "starts below its gas precharge, holding no oil (the "
                 "start pressure must be at least the precharge)", ["p_pre", "p0"])]

    def equations(self):
        return [eq(der(self.V_oil), self.port.q),
                eq(self.p, self.p_pre * (self.V0 / (self.V0 - self.V_oil)) ** self.n),
                eq(self.port.p, self.p)]
