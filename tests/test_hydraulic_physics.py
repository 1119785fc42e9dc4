"""The hydraulic components against physics: closed forms (an orifice
draining a volume, a mass on an oil spring, a pressure-dependent modulus),
conservation of the oil's mass and of energy, and the structural cases
(volumes joined directly, pistons on one incompressible line)."""
import math

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson, quad

from pdbfs.components import Fixed, Force, Mass, Spring
from pdbfs.components.hydraulic import (Accumulator, CheckValve, FlowSensor, FlowSource,
                                        LaminarLeak, Orifice, Piston, PressureSensor,
                                        PressureSource, ReliefValve, Tank, Volume,
                                        bulk_modulus_air, smooth_ramp)
import pdbfs
from pdbfs.errors import ModelError
from pdbfs.modelling import Component, Flange, eq
from pdbfs.rig import Rig

TIGHT = dict(rtol=1e-10, atol=1e-12)


class Draining(Rig):
    """A volume emptying through a turbulent orifice into a tank at 0 Pa."""

    def declare(self):
        self.vol = Volume(V=1e-3, K=1.5e9, p0=10e6)
        self.orifice = Orifice(Cd=0.7, A=1e-6, rho=870.0, dp_t=1.0)
        self.tank = Tank(p=0.0)
        self.sensor = PressureSensor()
        self.flow = FlowSensor()
        self.connect(self.vol.port, self.flow.port_a, self.sensor.port)
        self.connect(self.flow.port_b, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.tank.port)


def test_orifice_drains_a_volume_with_sqrt_p_falling_linearly():
    res = Draining().simulate(0.02, n_out=401, **TIGHT)
    p = res["vol.p"]
    K, V, Cd, A, rho, p0 = 1.5e9, 1e-3, 0.7, 1e-6, 870.0, 10e6
    want = math.sqrt(p0) - K * Cd * A * math.sqrt(2 / rho) / (2 * V) * res.t
    assert want[-1] > math.sqrt(1e5)          # stays far above dp_t and p_vap
    assert np.max(np.abs(np.sqrt(p) - want) / want) < 1e-7
    # the sensors read what the components hold
    assert np.allclose(res["sensor.p"], p, rtol=1e-12)
    assert np.allclose(res["flow.q"], res["orifice.q"], rtol=1e-12)


class Oscillator(Rig):
    """A mass on a piston over a sealed volume, preloaded to equilibrium."""

    def __init__(self, swept=True, **kw):
        self._swept = swept
        super().__init__(**kw)

    def declare(self):
        self.mass = Mass(m=10.0, v0=1e-4)
        self.load = Force(F=10e6 * 1e-3)            # p0*A: equilibrium at the start
        self.piston = Piston(A=1e-3)
        self.vol = Volume(V=1e-3, K=1.5e9, p0=10e6, swept=self._swept)
        self.connect(self.load.flange, self.mass.flange_a)
        self.connect(self.mass.flange_b, self.piston.flange)
        self.connect(self.piston.port, self.vol.port)
        if self._swept:
            self.connect(self.piston.q_swept, self.vol.q_swept)


@pytest.mark.parametrize("swept", [True, False])
def test_mass_on_oil_spring_rings_at_sqrt_KA2_over_Vm(swept):
    res = Oscillator(swept=swept).simulate(0.1, n_out=4001, **TIGHT)
    up = [t for t in res.crossings("mass.v", 0.0)]
    period = 2 * np.mean(np.diff(up))
    omega = math.sqrt(1.5e9 * 1e-6 / (1e-3 * 10.0))
    assert period == pytest.approx(2 * math.pi / omega, rel=1e-6)


class Impact(Rig):
    """A mass striking a piston over a sealed chamber that shrinks with the
    stroke; optionally a leak to a tank."""

    def __init__(self, p0=10e6, leak=False, **kw):
        self._p0, self._leak = p0, leak
        super().__init__(**kw)

    def declare(self):
        self.mass = Mass(m=50.0, v0=2.0)
        self.piston = Piston(A=1e-3)
        self.vol = Volume(V=1e-4, K=1.5e9, p0=self._p0, p_vap=0.0, swept=True)
        self.connect(self.mass.flange_b, self.piston.flange)
        self.connect(self.piston.port, self.vol.port)
        self.connect(self.piston.q_swept, self.vol.q_swept)
        if self._p0 > 0:
            self.load = Force(F=self._p0 * 1e-3)
            self.connect(self.load.flange, self.mass.flange_a)
        if self._leak:
            self.leak = LaminarLeak(G=1e-10)
            self.tank = Tank(p=0.0)
            self.connect(self.vol.port, self.leak.port_a)
            self.connect(self.leak.port_b, self.tank.port)


def test_sealed_chamber_keeps_its_oil():
    """rho/rho0 = exp((p - p0)/K) for a constant tangent modulus: the oil's
    mass rho*Vc stays rho0*V, with Vc from the mass's motion."""
    res = Impact(p0=100e6).simulate(0.01, n_out=2001, **TIGHT)
    Vc = 1e-4 - 1e-3 * (res["mass.s"] - res["mass.s"][0])
    mass = np.exp((res["vol.p"] - 100e6) / 1.5e9) * Vc / 1e-4
    assert np.ptp(res["vol.p"]) > 50e6 and np.min(res["vol.p"]) > 10e6   # squeezed, no vapour
    assert np.max(np.abs(mass - 1.0)) < 1e-8


def test_leaking_chamber_loses_what_flows_out():
    res = Impact(p0=100e6, leak=True).simulate(0.01, n_out=20001, **TIGHT)
    assert np.min(res["vol.p"]) > 10e6
    rho = np.exp((res["vol.p"] - 100e6) / 1.5e9)  # rho/rho0
    Vc = 1e-4 - 1e-3 * (res["mass.s"] - res["mass.s"][0])
    lost = 1e-4 - rho * Vc                         # oil gone, as volume at rho0
    flowed = cumulative_simpson(rho * res["leak.q"], x=res.t, initial=0.0)
    assert lost[-1] > 1e-7
    assert np.max(np.abs(lost - flowed)) < 1e-6 * lost[-1]


def test_energy_of_a_closed_rig_is_conserved_through_cavitation():
    """No preload: the mass squeezes the oil, is thrown back and leaves the
    chamber to vapour. Kinetic energy plus the oil's stored energy, the
    integral of p*A over the stroke (p from the clamp of K*ln(V/Vc)),
    stays what it was."""
    res = Impact(p0=0.0).simulate(0.01, n_out=2001, **TIGHT)
    K, V, A, w = 1.5e9, 1e-4, 1e-3, 1e3

    def p_of(x):
        return float(smooth_ramp(K * math.log(V / (V - A * x)), w))

    x = res["mass.s"] - res["mass.s"][0]
    stored = np.array([A * quad(p_of, 0.0, xi, epsabs=1e-12, epsrel=1e-12, limit=200)[0]
                       for xi in x])
    energy = 0.5 * 50.0 * res["mass.v"] ** 2 + stored
    assert res["mass.v"][-1] < -1.9 and res["vol.p_law"][-1] < -w   # rebounded, cavitating
    assert np.min(res["vol.p"]) >= 0.0
    assert np.max(np.abs(energy - energy[0])) < 1e-7 * energy[0]


class Compressed(Rig):
    """A fixed volume fed at a constant flow (no swept walls)."""

    def __init__(self, law, **kw):
        self._law = law
        super().__init__(**kw)

    def declare(self):
        self.vol = Volume(law=self._law, V=1e-3, K=1.5e9, p0=1e5)
        self.pump = FlowSource(Q=1e-3)
        self.connect(self.pump.port, self.vol.port)


def test_linear_modulus_follows_its_closed_form():
    """V dp/dt = (K + K1 p) Q: p = ((K + K1 p0) exp(K1 Q t/V) - K)/K1."""
    res = Compressed("linear").simulate(0.05, n_out=501, **TIGHT)
    K, K1, p0, Q, V = 1.5e9, 7.5, 1e5, 1e-3, 1e-3
    want = ((K + K1 * p0) * np.exp(K1 * Q * res.t / V) - K) / K1
    assert want[-1] > 90e6
    assert np.max(np.abs(res["vol.p"] - want) / want) < 1e-8


def test_entrained_air_modulus_integrates_to_the_fed_volume():
    """With air the fed volume Q*t is the integral of V/K_eff(p) dp."""
    rig = Compressed("air")
    res = rig.simulate(0.02, n_out=11, **TIGHT)
    K, a, n, pr = 1.5e9, 0.01, 1.0, 101325.0
    for t, p in zip(res.t[1:], res["vol.p"][1:]):
        fed = quad(lambda q: 1e-3 / float(bulk_modulus_air(q, K, a, n, pr)), 1e5, p,
                   epsrel=1e-12, limit=200)[0]
        assert fed == pytest.approx(1e-3 * t, rel=1e-7)
    # the air makes the oil softer at low pressure, not at high
    assert float(bulk_modulus_air(2e5, K, a, n, pr)) < 0.1 * K
    assert float(bulk_modulus_air(100e6, K, a, n, pr)) == pytest.approx(K, rel=0.01)


class Joined(Rig):
    def __init__(self, cavitation, **kw):
        self._cav = cavitation
        super().__init__(**kw)

    def declare(self):
        self.a = Volume(V=1e-3, K=1.5e9, p0=10e6, cavitation=self._cav)
        self.b = Volume(V=2e-3, K=1.5e9, p0=10e6, cavitation=self._cav)
        self.leak = LaminarLeak(G=1e-11)
        self.tank = Tank(p=0.0)
        self.connect(self.a.port, self.b.port, self.leak.port_a)
        self.connect(self.leak.port_b, self.tank.port)


def test_two_volumes_joined_directly_become_one():
    rig = Joined(cavitation=False)
    assert rig.compile().x_names == ["a.p_law"]
    res = rig.simulate(0.02, n_out=101, **TIGHT)
    want = 10e6 * np.exp(-1.5e9 * 1e-11 * res.t / 3e-3)
    assert np.max(np.abs(res["b.p"] - want)) < 1e-8 * 10e6


def test_two_cavitating_volumes_joined_directly_are_reduced_to_index_one():
    """clamp(a.p_law) = clamp(b.p_law) ties two states: differentiated once,
    b.p_law becomes algebraic, and the pair drains as one volume (IDAS)."""
    rig = Joined(cavitation=True)
    dae = rig.compile()
    assert dae.x_names == ["a.p_law"] and dae.z_names == ["b.p_law"]
    res = rig.simulate(0.02, n_out=101, **TIGHT)
    want = 10e6 * np.exp(-1.5e9 * 1e-11 * res.t / 3e-3)
    assert np.max(np.abs(res["b.p"] - want)) < 1e-7 * 10e6
    assert np.max(np.abs(res["a.p"] - res["b.p"])) < 1e-7 * 10e6
    with pytest.raises(pdbfs.PdbfsError, match="algebraic"):
        rig.simulate(0.02, backend="c")


class Cam(Component):
    """Two flanges tied by s_b = s_a^2: a constraint on positions."""

    def declare(self):
        self.flange_a = Flange()
        self.flange_b = Flange()

    def equations(self):
        return [eq(self.flange_b.s, self.flange_a.s ** 2),
                eq(self.flange_a.f, -2 * self.flange_a.s * self.flange_b.f)]


def test_a_constraint_on_positions_is_reduced_to_index_one():
    """s_b = s_a^2 between two masses (index 3): differentiated twice, the
    dummy derivatives fall on m2, whose position and velocity follow the
    constraint (tests/test_index_reduction.py checks the physics)."""
    class Cammed(Rig):
        def declare(self):
            self.m1 = Mass(m=1.0, s0=1.0, v0=0.5)
            self.m2 = Mass(m=1.0, s0=1.0, v0=1.0)
            self.cam = Cam()
            self.connect(self.m1.flange_b, self.cam.flange_a)
            self.connect(self.cam.flange_b, self.m2.flange_a)
    rig = Cammed()
    assert rig.compile().x_names == ["m1.s", "m1.v"]
    res = rig.simulate(0.5, n_out=51, **TIGHT)
    assert np.max(np.abs(res["m2.s"] - res["m1.s"] ** 2)) < 1e-12
    assert np.ptp(res["m1.s"]) > 0.1


class Lever(Rig):
    """Two pistons on one incompressible line: a hydraulic lever."""

    def declare(self):
        self.m1 = Mass(m=2.0, v0=1.0)
        self.m2 = Mass(m=3.0, v0=-0.25)
        self.p1 = Piston(A=1e-3)
        self.p2 = Piston(A=4e-3)
        self.k = Spring(k=1e4)
        self.frame = Fixed()
        self.connect(self.m1.flange_b, self.p1.flange)
        self.connect(self.m2.flange_b, self.p2.flange)
        self.connect(self.p1.port, self.p2.port)
        self.connect(self.m2.flange_a, self.k.flange_b)
        self.connect(self.k.flange_a, self.frame.flange)


def test_two_pistons_on_an_incompressible_line():
    """A1*v1 + A2*v2 = 0 removes one velocity state; the lever conserves
    energy, and rings at sqrt(k/(m2 + m1*(A2/A1)^2))."""
    rig = Lever()
    assert rig.compile().x_names == ["m1.s", "m1.v", "m2.s"]
    res = rig.simulate(2.0, n_out=4001, **TIGHT)
    assert np.max(np.abs(1e-3 * res["m1.v"] + 4e-3 * res["m2.v"])) < 1e-12
    x2 = res["m2.s"] - res["m2.s"][0]
    energy = 0.5 * 2 * res["m1.v"] ** 2 + 0.5 * 3 * res["m2.v"] ** 2 + 0.5 * 1e4 * x2 ** 2
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * energy[0]
    period = 2 * np.mean(np.diff(res.crossings("m2.v", 0.0)))
    assert period == pytest.approx(2 * math.pi / math.sqrt(1e4 / (3 + 2 * 16)), rel=1e-6)


class AccumulatorToVolume(Rig):
    def declare(self):
        self.acc = Accumulator(V0=1e-3, p_pre=5e6, p0=20e6, n=1.4)
        self.leak = LaminarLeak(G=1e-10)
        self.vol = Volume(V=1e-3, K=1.5e9, p0=1e6)
        self.check = CheckValve(p_crack=1e5, dp_open=1e5, A=1e-6)
        self.connect(self.acc.port, self.leak.port_a, self.check.port_a)
        self.connect(self.leak.port_b, self.vol.port, self.check.port_b)


def test_accumulator_and_volume_share_their_oil_and_settle_at_one_pressure():
    res = AccumulatorToVolume().simulate(0.5, n_out=501, **TIGHT)
    v_acc = res["acc.V_oil"]
    v_vol = 1e-3 / 1.5e9 * (res["vol.p"] - 1e6)    # oil pushed into the fixed volume
    assert np.max(np.abs((v_acc + v_vol) - (v_acc[0] + v_vol[0]))) < 1e-9 * v_acc[0]
    assert res["acc.p"][-1] == pytest.approx(res["vol.p"][-1], rel=1e-6)
    gas = res["acc.p"] * (1e-3 - v_acc) ** 1.4
    assert np.allclose(gas, 5e6 * 1e-3 ** 1.4, rtol=1e-10)
    assert np.min(res["check.q"]) >= 0.0           # the check valve never flows backwards


class Relieved(Rig):
    def declare(self):
        self.pump = FlowSource(Q=1e-4)
        self.vol = Volume(V=1e-4, K=1.5e9, p0=1e5)
        self.relief = ReliefValve(p_crack=20e6, dp_open=2e6, A=1e-5)
        self.tank = Tank()
        self.connect(self.pump.port, self.vol.port, self.relief.port_a)
        self.connect(self.relief.port_b, self.tank.port)


def test_relief_valve_holds_the_pressure_where_it_passes_the_pump_flow():
    res = Relieved().simulate(0.2, n_out=201, **TIGHT)
    p = res["vol.p"][-1]
    assert 20e6 < p - 101325 < 22e6                 # above cracking, not past full opening
    assert res["relief.q"][-1] == pytest.approx(1e-4, rel=1e-6)


def test_pressure_source_as_a_function_of_time_drives_a_leak():
    class Ramp(Rig):
        def declare(self):
            self.src = PressureSource(function=lambda t: 1e6 + 1e8 * t)
            self.leak = LaminarLeak(G=1e-10)
            self.vol = Volume(V=1e-3, K=1.5e9, p0=0.0, p_vap=0.0)
            self.connect(self.src.port, self.leak.port_a)
            self.connect(self.leak.port_b, self.vol.port)
    res = Ramp().simulate(0.01, n_out=11, **TIGHT)
    assert np.allclose(res["src.q_out"], 1e-10 * (1e6 + 1e8 * res.t - res["vol.p"]), rtol=1e-9)
    assert res["src.q_out"][-1] > 5e-5


def test_cylinder_is_a_piston_over_its_own_shrinking_chamber():
    """A Cylinder with its port left closed rings as the hand-wired piston
    and swept volume of Oscillator do, and keeps its oil."""
    from pdbfs.components.hydraulic import Cylinder

    class Sealed(Rig):
        def declare(self):
            self.mass = Mass(m=10.0, v0=1e-4)
            self.load = Force(F=10e6 * 1e-3)
            self.cyl = Cylinder(A=1e-3, V=1e-3, K=1.5e9, p0=10e6)
            self.connect(self.load.flange, self.mass.flange_a)
            self.connect(self.mass.flange_b, self.cyl.flange)
    a = Sealed().simulate(0.05, n_out=1001, **TIGHT)
    b = Oscillator(swept=True).simulate(0.05, n_out=1001, **TIGHT)
    assert np.max(np.abs(a["cyl.chamber.p"] - b["vol.p"])) < 1e-9 * 10e6
    assert np.allclose(a["cyl.chamber.Vc"], 1e-3 - 1e-3 * (a["mass.s"] - a["mass.s"][0]),
                       rtol=0, atol=1e-15)

