"""ElasticBar (issue 10): the lumped bar carries the continuum bar's axial
waves, checked against closed forms: the transit time L/c, the free-end
velocity doubling, and Saint-Venant's bonded impact of a rigid mass."""
import math
import warnings

import casadi as ca
import numpy as np
import pytest

from pdbfs.components import (BarResolutionWarning, ElasticBar, Force, Mass, Spring,
                              check_bar_resolution)
from pdbfs.components.translational.bar import bar_resolution
from pdbfs.errors import ParameterError
from pdbfs.models import PAPER_SIGNALS, RIGS, bar_piston_rig, paper_rig
from pdbfs.rig import Rig

# a thin steel rod, 1 m: c = 5172 m/s, L/c = 0.19 ms, Z = A*sqrt(E*rho) = 4.06e4 N.s/m
E, RHO, A, L = 2.1e11, 7850.0, 1e-3, 1.0
C = math.sqrt(E / RHO)
Z = A * math.sqrt(E * RHO)
T = L / C


class StruckBar(Rig):
    """A free bar pushed at flange_a by a constant force F from t = 0."""

    def __init__(self, n, F):
        self._n, self._F = n, F
        super().__init__()

    def declare(self):
        self.bar = ElasticBar(n=self._n, L=L, A=A, E=E, rho=RHO)
        self.push = Force(F=self._F)
        self.connect(self.push.flange, self.bar.flange_a)


class Blow(Rig):
    """A rigid striker M at v0 hits a free bar at rest through a linear
    spring of the bar's own link stiffness n*E*A/L.

    Why this contact: connecting the striker's flange to flange_a directly
    makes striker and segment 1 one rigid body, whose start velocities
    disagree (a ModelError), and the contact force would not be a variable.
    A contact much stiffer than a link is worse: the first segment then
    rings between it and link 1 above the chain's cut-off 2*c*n/L, a mode
    that cannot radiate into the bar and never decays. With the link
    stiffness the striker simply joins the chain as a heavy end mass, the
    lumped form of a bonded impact."""

    def __init__(self, n, M, v0):
        self._n, self._M, self._v0 = n, M, v0
        super().__init__()

    def declare(self):
        n = self._n
        self.bar = ElasticBar(n=n, L=L, A=A, E=E, rho=RHO)
        self.striker = Mass(m=self._M, v0=self._v0)
        self.contact = Spring(k=n * E * A / L)
        self.connect(self.striker.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.bar.flange_a)


def first_crossing(t, y, level):
    k = int(np.flatnonzero(y > level)[0])
    return float(np.interp(level, y[k - 1:k + 1], t[k - 1:k + 1]))


# ------------------------------------------------------------------ a. transit time
@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_the_front_reaches_the_free_end_after_L_over_c_and_doubles_its_velocity():
    """A force step F on a free bar sends a front of particle velocity F/Z;
    at the free end it reflects and the end moves at 2F/Z from t = L/c on.
    The end's arrival (half of 2F/Z) is within 2 % of L/c and approaches it
    as n grows."""
    F = 1e4
    errors = []
    for n in (100, 400):
        res = StruckBar(n, F).simulate(2 * T, n_out=401)
        v_end = res[f"bar.seg{n}.v"]
        arrival = first_crossing(res.t, v_end, F / Z)
        errors.append(abs(arrival / T - 1))
        assert arrival == pytest.approx(T, rel=0.02)
        # nothing moves at the far end before the front (beyond the chain's tail)
        assert np.max(np.abs(v_end[res.t < 0.8 * T])) < 0.01 * F / Z
        # free-end doubling, averaged over the ringing behind the front
        late = res.t > 1.5 * T
        assert np.mean(v_end[late]) == pytest.approx(2 * F / Z, rel=0.01)
        # the centre of mass moves as a rigid body: v = F*t/m
        s_cm = res["bar.s"][-1]
        assert s_cm == pytest.approx(F * res.t[-1] ** 2 / (2 * RHO * A * L), rel=1e-4)
    assert errors[1] < errors[0]


@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_the_front_crosses_each_link_in_one_segment_transit_time():
    n = 100
    res = StruckBar(n, 1e4).simulate(0.8 * T, n_out=801)
    links = range(10, 71, 10)
    arrival = [first_crossing(res.t, -res[f"bar.link{i}.f"], 0.5e4) for i in links]
    slope = np.polyfit(np.array(list(links)) * L / n, arrival, 1)[0]
    assert 1 / slope == pytest.approx(C, rel=0.01)


# ------------------------------------------------------------------ b. Saint-Venant
def _blow_error(n, M, v0):
    """Largest deviation of the contact force from Z*v0*exp(-Z*t/M), relative
    to Z*v0, after the rise (t >= M/(4Z)) and before the reflection from the
    far end returns (2L/c)."""
    res = Blow(n, M, v0).simulate(1.8 * T, n_out=361)
    force = -res["contact.f"]
    exact = Z * v0 * np.exp(-Z * res.t / M)
    window = res.t >= 0.25 * M / Z
    return float(np.max(np.abs(force - exact)[window]) / (Z * v0))


@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_mass_striking_a_bar_gives_saint_venants_exponential_force():
    M, v0 = 0.25 * RHO * A * L, 3.0      # M/Z = L/(4c): 8 decay times before 2L/c
    err_coarse = _blow_error(50, M, v0)
    err_fine = _blow_error(200, M, v0)
    assert err_fine < 0.03
    # first order in the segment length: 4x the segments, about 1/4 the error
    assert err_coarse / err_fine > 2.5


# ------------------------------------------------------------------ c. bad input
@pytest.mark.parametrize("n", [0, -3, 2.5, True, "4", None])
def test_bad_segment_count_is_named(n):
    with pytest.raises(ParameterError, match=r"ElasticBar: n = .*whole number"):
        ElasticBar(n=n)


@pytest.mark.parametrize("name", ["L", "A", "E", "rho"])
@pytest.mark.parametrize("value", [0.0, -2.0])
def test_non_positive_bar_parameters_are_rejected(name, value):
    with pytest.raises(ParameterError, match=f"ElasticBar.{name} = .*must be > 0"):
        ElasticBar(n=3, **{name: value})
    with pytest.raises(ParameterError, match=f"bar.{name} = .*must be > 0"):
        StruckBar(3, 1.0).simulate(1e-4, n_out=11, params={f"bar.{name}": value})


def test_resolution_warning_gives_the_factor_and_the_segments_needed():
    bar = ElasticBar(n=10, L=L, E=E, rho=RHO)
    tau = T / 10
    with pytest.warns(BarResolutionWarning, match="times") as caught:
        r = check_bar_resolution(bar, tau / 5.2)
    assert r.factor == pytest.approx(5.2)
    assert r.n_min == 52 and "5.2 times" in str(caught[0].message)
    assert "n >= 52" in str(caught[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_bar_resolution({"L": L, "E": E, "rho": RHO, "n": 10}, tau).resolved
        assert check_bar_resolution(bar, 2 * tau).factor == pytest.approx(0.5)
    # n_min is exactly enough
    assert bar_resolution(L, E, RHO, r.n_min, tau / 5.2).resolved
    assert not bar_resolution(L, E, RHO, r.n_min - 1, tau / 5.2).resolved
    with pytest.raises(ParameterError, match="dt_out"):
        bar_resolution(L, E, RHO, 10, 0.0)


# ------------------------------------------------------------------ d. the rig
def test_bar_piston_rig_is_close_to_the_rigid_piston_rig():
    """The steel piston (E*A/L = 3.5e9 N/m) is 16x stiffer than the oil,
    so the oil sees nearly a rigid piston."""
    rig = bar_piston_rig(20)
    key = PAPER_SIGNALS["pressure"]
    bar = rig.simulate(t_end=0.02, n_out=401)
    rigid = paper_rig().simulate(0.02, n_out=401)
    assert bar.peak(key)[1] == pytest.approx(rigid.peak(key)[1], rel=0.03)
    assert rig.rig_name() == "pdbfs_bar20" and RIGS["bar-piston"]().n == 30
    # the segments add up to the paper's m2, and to rho*A*L
    dae = rig.compile()
    p = ca.DM(dae.p_default())
    masses = [float(ca.Function("m", [dae.p], [dae.calculated[f"piston.seg{i}.m"][0]])(p))
              for i in range(1, 21)]
    assert sum(masses) == pytest.approx(241.7, rel=1e-9)
    assert max(masses) == pytest.approx(min(masses), rel=1e-12)
    par = bar.params
    assert sum(masses) == pytest.approx(par["piston.rho"] * par["piston.A"] * par["piston.L"])


@pytest.mark.filterwarnings("ignore::pdbfs.components.BarResolutionWarning")  # sampled finer on purpose
def test_one_segment_bar_piston_is_the_paper_rig():
    a = paper_rig().simulate(0.02, n_out=401)
    b = bar_piston_rig(1).simulate(0.02, n_out=401)
    assert np.max(np.abs(a["oil.pressure"] - b["oil.pressure"])) <= 1e-9 * np.max(a["oil.pressure"])


def test_rig_checks_the_resolution_of_its_piston():
    rig = bar_piston_rig(20)
    tau = rig.piston.values()["L"] / (20 * math.sqrt(2.1e11 / 7850))
    with pytest.warns(BarResolutionWarning, match="ElasticBar 'piston'.*times"):
        rig.check_resolution(tau / 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert rig.check_resolution(2 * tau).resolved
        # a shorter piston has shorter segments
        assert rig.check_resolution(tau / 2, params={"piston.L": 0.25}).resolved
