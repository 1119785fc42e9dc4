"""ElasticBar's material damping (Kelvin-Voigt, ``eta``): each mode's damping
ratio against the closed form of the lumped chain, the energy its dampers
take against the energy the rig loses, the parameter set per run, and what
it does to a fine chain's explicit steps."""
import math

import numpy as np
import pytest

from pdbfs.components import ElasticBar, Mass, Spring
from pdbfs.errors import ParameterError
from pdbfs.models import bar_piston_rig
from pdbfs.models.bar_piston import PISTON_LENGTH, STEEL_E, STEEL_RHO
from pdbfs.rig import Rig

E, RHO, A, L = 2.1e11, 7850.0, 1e-3, 1.0
C = math.sqrt(E / RHO)
M, V0 = 0.25 * RHO * A * L, 3.0      # the striker


def eta_for(zeta_max, n, length=L, c=C, e=E):
    """The viscosity that gives a bar of n segments' highest mode the damping ratio zeta_max."""
    return zeta_max * e * length / (n * c)


class FreeBar(Rig):
    def __init__(self, n, **params):
        self._n, self._kw = n, params
        super().__init__()

    def declare(self):
        self.bar = ElasticBar(n=self._n, L=L, A=A, E=E, rho=RHO, **self._kw)


class Blow(Rig):
    """A striker hits a free bar through a spring of the bar's link stiffness."""

    def __init__(self, n, **params):
        self._n, self._kw = n, params
        super().__init__()

    def declare(self):
        n = self._n
        self.bar = ElasticBar(n=n, L=L, A=A, E=E, rho=RHO, **self._kw)
        self.striker = Mass(m=M, v0=V0)
        self.contact = Spring(k=n * E * A / L)
        self.connect(self.striker.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.bar.flange_a)


def test_each_mode_has_the_kelvin_voigt_damping_ratio():
    # stiffness-proportional damping keeps the chain's modes: omega_j =
    # (2c/h) sin(j pi/2n) undamped, zeta_j = eta omega_j / (2E)
    n = 8
    eta = eta_for(0.5, n)
    modes = FreeBar(n, eta=eta).modes()
    moving = modes[modes["omega"] > 1.0]
    j = np.arange(1, n)
    omega = 2 * C * n / L * np.sin(j * math.pi / (2 * n))
    np.testing.assert_allclose(moving["omega"], omega, rtol=1e-9)
    np.testing.assert_allclose(moving["damping"], eta * omega / (2 * E), rtol=1e-9)
    assert moving["damping"].iloc[-1] == pytest.approx(0.5 * math.sin((n - 1) * math.pi / (2 * n)))


@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_the_dampers_take_the_energy_the_rig_loses():
    n = 10
    rig = Blow(n, eta=eta_for(0.3, n))
    t_end = 1.8 * L / C
    res = rig.simulate(t_end, n_out=20001, rtol=1e-10, atol=1e-14)
    m = RHO * A * L / n
    kinetic = 0.5 * M * res["striker.v"] ** 2 + sum(
        0.5 * m * res[f"bar.seg{i}.v"] ** 2 for i in range(1, n + 1))
    k_link = n * E * A / L
    springs = 0.5 * k_link * (res["contact.s_rel"] ** 2 + sum(
        res[f"bar.link{i}.s_rel"] ** 2 for i in range(1, n)))
    power = sum(res[f"bar.damper{i}.f"] * res[f"bar.damper{i}.v_rel"] for i in range(1, n))
    dissipated = np.concatenate([[0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(res.t))])
    start = kinetic[0] + springs[0]
    assert dissipated[-1] > 0.05 * start        # the damping does take energy
    np.testing.assert_allclose(kinetic + springs + dissipated, start, rtol=1e-7)


@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_eta_is_set_per_run_and_checked():
    n = 6
    eta = eta_for(0.2, n)
    built = Blow(n, eta=eta).simulate(1e-4, n_out=101)
    rig = Blow(n)
    dae = rig.compile()
    assert dae.p_default()[dae.p_names.index("bar.eta")] == 0.0   # the default bar is undamped
    per_run = rig.simulate(1e-4, n_out=101, params={"bar.eta": eta})
    undamped = rig.simulate(1e-4, n_out=101)
    np.testing.assert_allclose(per_run["contact.f"], built["contact.f"], rtol=1e-12, atol=1e-9)
    assert np.max(np.abs(per_run["contact.f"] - undamped["contact.f"])) > 1e-3 * np.max(
        np.abs(undamped["contact.f"]))
    with pytest.raises(ParameterError, match="bar.eta"):
        rig.simulate(1e-4, params={"bar.eta": -1.0})


def test_damping_the_highest_mode_shortens_a_fine_chains_explicit_run():
    n = 32
    rig = bar_piston_rig(n)
    eta = eta_for(0.01, n, PISTON_LENGTH, math.sqrt(STEEL_E / STEEL_RHO), STEEL_E)
    plain = rig.simulate()
    damped = rig.simulate(params={"piston.eta": eta})
    assert plain.settings["method"] == damped.settings["method"] == "erk"
    assert damped.stats["steps"] < 0.8 * plain.stats["steps"]
    # the pulse's slow modes are barely damped: the peak moves by a few 1e-5 of itself
    peak, peak_damped = plain.summary()["peak_pressure"], damped.summary()["peak_pressure"]
    assert peak_damped < peak
    assert peak_damped == pytest.approx(peak, rel=1e-4)
