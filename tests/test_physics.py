"""Physics checks of the acausal core on rigs built from the library."""
import numpy as np
import pytest
from scipy.special import beta

import pdbfs
from pdbfs.components import (Damper, Fixed, Force, HertzContact, ImpactContact, Mass,
                              OilColumn, Spring)
from pdbfs.models import paper_rig

TIGHT = dict(rtol=1e-11, atol=1e-14)


class TwoBodies(pdbfs.Rig):
    """Body 1 strikes body 2 at rest through a contact; nothing else acts."""

    def __init__(self, contact, m1=2.0, m2=3.0, v0=1.5):
        self._setup = (contact, m1, m2, v0)
        super().__init__()

    def declare(self):
        contact, m1, m2, v0 = self._setup
        self.body1 = Mass(m=m1, v0=v0)
        self.body2 = Mass(m=m2)
        self.contact = contact
        self.connect(self.body1.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.body2.flange_a)


def _energy_paper(res, k1, n, k2, k3):
    m = {b: res.params[f"{b}.m"] for b in ("hammer", "piston", "breech")}
    ke = sum(0.5 * m[b] * res[f"{b}.v"] ** 2 for b in m)
    d = np.clip(res["hammer.s"] - res["piston.s"], 0, None)
    do = np.clip(res["piston.s"] - res["breech.s"], 0, None)
    return ke + k1 * d ** (n + 1) / (n + 1) + 0.5 * k2 * do ** 2 + 0.5 * k3 * res["breech.s"] ** 2


def test_energy_is_conserved_without_damping():
    res = paper_rig().simulate(0.02, params={"contact.D": 0.0, "seal.c": 0.0}, **TIGHT)
    p = res.params
    E = _energy_paper(res, p["contact.k"], p["contact.n"], p["oil.k"], p["mount.k"])
    drift = np.max(np.abs(E - E[0])) / E[0]
    assert drift < 1e-6
    # and the pulse is there: energy really moved into the springs
    assert res.summary()["peak_pressure"] > 5e7


def test_energy_is_lost_with_damping():
    res = paper_rig().simulate(0.02, **TIGHT)
    p = res.params
    E = _energy_paper(res, p["contact.k"], p["contact.n"], p["oil.k"], p["mount.k"])
    assert E[-1] < 0.95 * E[0]
    assert np.all(np.diff(E) < 1e-6 * E[0])   # never gains energy


def test_hertz_impact_matches_closed_form():
    k, m1, m2, v = 1e9, 2.0, 3.0, 1.5
    rig = TwoBodies(HertzContact(k=k, n=1.5), m1, m2, v)
    res = rig.simulate(1.2e-3, n_out=401, **TIGHT)
    m = m1 * m2 / (m1 + m2)
    d_max = (5 * m * v ** 2 / (4 * k)) ** 0.4
    # contact time: 2 d_max / v * int_0^1 dx / sqrt(1 - x^2.5) = 2 d_max / v * 0.4 B(0.4, 0.5)
    t_c = 2 * d_max / v * 0.4 * beta(0.4, 0.5)
    assert res.peak("contact.d")[1] == pytest.approx(d_max, rel=1e-4)
    cross = res.crossings("contact.d", 0.0)
    assert len(cross) == 1
    assert cross[0] == pytest.approx(t_c, rel=1e-4)
    assert t_c == pytest.approx(2.94 * d_max / v, rel=2e-3)   # PHYSICS.md's rounded constant


@pytest.mark.parametrize("law", ["lankarani-nikravesh", "hunt-crossley", "flores"])
def test_damped_impact_restitution_and_momentum(law):
    m1, m2, v, e = 2.0, 3.0, 1.5, 0.95
    contact = ImpactContact(law=law, k=1e9, n=1.5)
    rig = TwoBodies(contact, m1, m2, v)
    res = rig.simulate(1.2e-3, n_out=301, params={"contact.e": e, "contact.v_impact": v},
                       **TIGHT)
    mom = m1 * res["body1.v"] + m2 * res["body2.v"]
    assert np.max(np.abs(mom - mom[0])) < 1e-9 * abs(mom[0])
    assert res["contact.fc"].min() >= 0.0            # the contact never pulls
    assert len(res.crossings("contact.d", 0.0)) == 1  # they separated
    e_out = (res["body2.v"][-1] - res["body1.v"][-1]) / v
    tol = 0.005 if law == "lankarani-nikravesh" else 0.02
    assert e_out == pytest.approx(e, abs=tol)


def test_restitution_estimate_from_force_history():
    """Guo & Batzer's impulse ratio: 1 for a purely elastic impact; split at
    maximum indentation it equals the velocity restitution of a free impact."""
    from pdbfs.simulation.results.impulse import restitution_from_force
    m1, m2, v = 2.0, 3.0, 1.5
    res = TwoBodies(HertzContact(k=1e9), m1, m2, v).simulate(1.2e-3, n_out=4001, **TIGHT)
    assert restitution_from_force(res.t, res["contact.fc"]) == pytest.approx(1.0, abs=1e-3)

    rig = TwoBodies(ImpactContact(law="lankarani-nikravesh", k=1e9, n=1.5), m1, m2, v)
    res = rig.simulate(1.2e-3, n_out=4001, params={"contact.v_impact": v, "contact.e": 0.9},
                       **TIGHT)
    e_vel = (res["body2.v"][-1] - res["body1.v"][-1]) / v
    t_max_d = res.peak("contact.d")[0]
    e_split = restitution_from_force(res.t, res["contact.fc"], t_split=t_max_d)
    assert e_split == pytest.approx(e_vel, abs=2e-3)
    assert restitution_from_force(res.t, res["contact.fc"]) > e_split   # peak comes earlier


class RigidPair(pdbfs.Rig):
    """Two masses bolted together on a spring to the frame, pushed by a force."""

    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=400.0)
        self.m1 = Mass(m=1.5)
        self.m2 = Mass(m=2.5)
        self.push = Force(F=20.0)
        self.connect(self.frame.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.m2.flange_a)   # rigid: shared flange
        self.connect(self.m2.flange_b, self.push.flange)


class OneMass(pdbfs.Rig):
    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=400.0)
        self.m1 = Mass(m=4.0)
        self.push = Force(F=20.0)
        self.connect(self.frame.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.push.flange)


def test_rigidly_connected_masses_are_one_mass():
    pair, one = RigidPair(), OneMass()
    dae = pair.compile()
    assert len(dae.x_names) == 2               # one body: one position, one velocity
    r2 = pair.simulate(1.0, n_out=201, **TIGHT)
    r1 = one.simulate(1.0, n_out=201, **TIGHT)
    w = np.sqrt(400.0 / 4.0)
    exact = 20.0 / 400.0 * (1 - np.cos(w * r2.t))
    assert np.max(np.abs(r2["m2.s"] - exact)) < 1e-8
    assert np.max(np.abs(r2["m1.s"] - r1["m1.s"])) < 1e-9
    assert np.max(np.abs(r2["m2.v"] - r1["m1.v"])) < 1e-8
    # the bolt carries the force that accelerates m2: f = m2*a - F
    bolt = r2["m2.flange_a.f"]
    assert np.max(np.abs(bolt - (2.5 * r2["m2.a"] - 20.0))) < 1e-6


def test_inconsistent_start_of_rigid_masses_is_an_error():
    rig2 = RigidPair()
    rig2.m2._params["v0"].value = 1.0
    with pytest.raises(pdbfs.ModelError, match="m2.v"):
        rig2.compile()


def test_maxwell_element_node_becomes_a_state():
    """A spring in series with a damper: the massless node has a state."""
    class Maxwell(pdbfs.Rig):
        def declare(self):
            self.frame = Fixed()
            self.spring = Spring(k=100.0)
            self.damper = Damper(c=10.0)
            self.mass = Mass(m=1.0, v0=1.0)
            self.connect(self.frame.flange, self.damper.flange_a)
            self.connect(self.damper.flange_b, self.spring.flange_a)
            self.connect(self.spring.flange_b, self.mass.flange_a)

    rig = Maxwell()
    assert len(rig.compile().x_names) == 3
    res = rig.simulate(5.0, n_out=501, **TIGHT)
    # energy: kinetic + spring = initial - dissipated in the damper
    ke = 0.5 * res["mass.v"] ** 2
    pe = 0.5 * 100.0 * res["spring.s_rel"] ** 2
    dissipated = np.concatenate([[0], np.cumsum(
        np.diff(res.t) * 0.5 * (10.0 * res["damper.v_rel"][1:] ** 2
                                + 10.0 * res["damper.v_rel"][:-1] ** 2))])
    assert np.max(np.abs(ke + pe + dissipated - 0.5)) < 2e-3


def test_oil_bulk_modulus_gives_stiffness():
    oil = OilColumn(bulk_modulus=True)
    class R(pdbfs.Rig):
        def declare(self):
            self.frame = Fixed()
            self.piston = Mass(m=10.0, v0=1.0)
            self.oil = oil
            self.connect(self.piston.flange_b, self.oil.flange_a)
            self.connect(self.oil.flange_b, self.frame.flange)
    rig = R()
    dae = rig.compile()
    assert "oil.k" in dae.calculated and "oil.K" in dae.p_names
    K, A, L = 2.2e9, 2.270e-2, 0.2
    k = K * A / L
    res = rig.simulate(0.01, n_out=1001, **TIGHT)
    # half a period of the compressed column, then the piston leaves at -1 m/s
    assert res.crossings("oil.d", 0.0)[0] == pytest.approx(np.pi * np.sqrt(10.0 / k), rel=1e-6)
    assert res.peak("oil.pressure")[1] == pytest.approx(np.sqrt(10.0 * k) * 1.0 / A, rel=1e-6)
