"""A volume filled through an orifice from a 1e7 Pa SignalPressure: near
equilibrium the orifice's flow law is linear and steep, and the explicit
method's steps are held by stability; where a step's h*lambda was past the
end of the method's stability the fast mode was not damped, and its dense
output put the pressure 22 Pa above its supply at the defaults (2.2e-6 of
scale; the implicit methods and CasADi stay within a tenth of a pascal). The
pressure never exceeds the supply by more than a few tolerances' share of
it, on both back ends, and the explicit method's pressure is a tight
implicit run's."""
import numpy as np
import pytest

import pdbfs
from pdbfs.components import blocks as B
from pdbfs.components import hydraulic as H

SUPPLY = 1e7


class Filling(pdbfs.Rig):
    """A 1 l volume filled through an orifice from a pressure given as a signal."""

    def declare(self):
        self.cmd = B.Constant(k=SUPPLY, unit="Pa")
        self.src = H.SignalPressure()
        self.orifice = H.Orifice()
        self.vol = H.Volume()
        self.connect(self.cmd.y, self.src.u)
        self.connect(self.src.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.vol.port)


@pytest.fixture(scope="module")
def rig():
    return Filling()


@pytest.mark.parametrize("backend", ["c", "casadi"])
@pytest.mark.parametrize("t_end", [0.02, 0.2])
def test_a_volume_filled_from_a_supply_stays_below_it(rig, backend, t_end):
    res = rig.simulate(t_end, backend=backend)
    p = res["vol.p"]
    rtol = res.settings["rtol"]
    assert p[0] < 0.02 * SUPPLY and p[-1] == pytest.approx(SUPPLY, rel=rtol)   # filled
    assert np.max(p) - SUPPLY < 5 * rtol * SUPPLY       # a global error of a few tolerances


def test_the_explicit_methods_fill_is_the_implicit_ones(rig):
    erk = rig.simulate(0.02, n_out=20001, backend="c", method="erk")
    bdf = rig.simulate(0.02, n_out=20001, backend="c", method="bdf", rtol=1e-10, atol=1e-6)
    assert np.max(np.abs(erk["vol.p"] - bdf["vol.p"])) < 2e-7 * SUPPLY
