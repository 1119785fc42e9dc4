"""Dissipation becomes heat: what a damper, a seal, an impact contact, a
leak or an orifice dissipates is the heat its capacitor receives, to 1e-6
of the energy lost, on both back ends and in the FMU; the temperature laws
change the oil column's stiffness and the seal's friction as their closed
forms say, through a heat port as through the parameter T, and switched off
they change nothing."""
import math

import fmpy
import numpy as np
import pytest

import pdbfs
from pdbfs.components import (Damper, Fixed, ImpactContact, Mass, OilColumn, SealFriction,
                              Spring)
from pdbfs.components import hydraulic as H
from pdbfs.components import thermal as TH
from pdbfs.errors import ParameterError
from pdbfs.fmu import export_fmu

BACKENDS = ["c", "casadi"]
TIGHT = dict(rtol=1e-10, atol=1e-12)
M, K, V0, T0, CH = 2.0, 800.0, 1.5, 300.0, 0.5      # kg, N/m, m/s, K, J/K


class Oscillator(pdbfs.Rig):
    """A mass on a spring to the frame, damped by ``damper`` (a Damper, or a
    SealFriction with a Coulomb part) whose heat goes to a small capacitor."""

    def __init__(self, kind: str = "damper", **kw):
        self._kind = kind
        super().__init__(**kw)

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=M, v0=V0)
        self.spring = Spring(k=K)
        self.damper = Damper(c=3.0, heat_port=True) if self._kind == "damper" else \
            SealFriction(c=2.0, F_c=1.5, v_eps=0.05, heat_port=True)
        self.heat = TH.HeatCapacitor(C=CH, T0=T0)
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.body.flange_a, self.spring.flange_b, self.damper.flange_b)
        self.connect(self.damper.heat_port, self.heat.port)


def _lost_and_heat(s, v, T):
    """(mechanical energy lost, heat received), J, along the run."""
    lost = 0.5 * M * V0 ** 2 - (0.5 * M * np.asarray(v) ** 2 + 0.5 * K * np.asarray(s) ** 2)
    return lost, CH * (np.asarray(T) - T0)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("kind", ["damper", "seal"])
def test_a_damped_oscillators_lost_energy_is_its_capacitors_heat(backend, kind):
    res = Oscillator(kind).simulate(3.0, n_out=301, backend=backend, **TIGHT)
    lost, heat = _lost_and_heat(res["body.s"], res["body.v"], res["heat.T"])
    assert lost[-1] > 0.9 * 0.5 * M * V0 ** 2          # most of it is gone by then
    assert np.max(np.abs(lost - heat)) < 1e-6 * lost[-1]
    np.testing.assert_allclose(res["damper.loss_power"], -res["damper.heat_port.Q_flow"],
                               rtol=0, atol=0)




class Impact(pdbfs.Rig):
    """A striker hits a body resting on a spring through an ImpactContact
    (Hertz plus hysteresis damping, law Lankarani-Nikravesh): the
    hysteresis loop's energy is the contact's heat."""

    def declare(self):
        self.frame = Fixed()
        self.striker = Mass(m=10.0, v0=2.0)
        self.body = Mass(m=5.0)
        self.contact = ImpactContact(law="lankarani-nikravesh", k=1e9, e=0.6, heat_port=True)
        self.mount = Spring(k=1e6)
        self.heat = TH.HeatCapacitor(C=1.0, T0=T0)
        self.connect(self.striker.flange_b, self.contact.flange_a)
        self.connect(self.contact.flange_b, self.body.flange_a)
        self.connect(self.body.flange_b, self.mount.flange_a)
        self.connect(self.mount.flange_b, self.frame.flange)
        self.connect(self.contact.heat_port, self.heat.port)


@pytest.mark.parametrize("backend", BACKENDS)
def test_an_impacts_hysteresis_energy_is_the_contacts_heat(backend):
    res = Impact().simulate(0.01, n_out=1001, backend=backend, **TIGHT)
    d = np.maximum(res["contact.d"], 0.0)
    mech = (0.5 * 10.0 * res["striker.v"] ** 2 + 0.5 * 5.0 * res["body.v"] ** 2
            + 0.5 * 1e6 * res["body.s"] ** 2 + 1e9 * d ** 2.5 / 2.5)
    lost, heat = mech[0] - mech, 1.0 * (res["heat.T"] - T0)
    assert lost[-1] > 0.2 * mech[0]                     # e = 0.6 loses a good part
    assert np.max(np.abs(lost - heat)) < 1e-6 * lost[-1]
    np.testing.assert_array_equal(res["contact.loss_power"], res["contact.damping.loss_power"])


class Leak(pdbfs.Rig):
    """Two sealed volumes at different pressures joined by ``link`` (a
    LaminarLeak or an Orifice) whose heat goes to a capacitor."""

    def __init__(self, link: str, **kw):
        self._link = link
        super().__init__(**kw)

    def declare(self):
        self.high = H.Volume(V=1e-3, K=1.5e9, p0=20e6, cavitation=False)
        self.low = H.Volume(V=2e-3, K=1.5e9, p0=1e6, cavitation=False)
        self.link = H.LaminarLeak(G=1e-11, heat_port=True) if self._link == "leak" else \
            H.Orifice(A=2e-7, dp_t=1e3, heat_port=True)
        self.heat = TH.HeatCapacitor(C=1.0, T0=T0)
        self.connect(self.high.port, self.link.port_a)
        self.connect(self.link.port_b, self.low.port)
        self.connect(self.link.heat_port, self.heat.port)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("link", ["leak", "orifice"])
def test_the_power_of_a_throttled_flow_is_the_heat(backend, link):
    """A volume's elastic energy is V p^2 / (2 K) (its equation V dp/dt = K q):
    what the two lose together is what the leak turned into heat."""
    res = Leak(link).simulate(0.5, n_out=501, backend=backend, **TIGHT)
    stored = 1e-3 * res["high.p"] ** 2 / 3e9 + 2e-3 * res["low.p"] ** 2 / 3e9
    lost, heat = stored[0] - stored, res["heat.T"] - T0
    assert lost[-1] > 0.5 * stored[0] * (1 - (2 / 3 * 20 + 1 / 3) ** 2 / (20 ** 2 / 2 + 1 / 2) / 3)
    assert np.max(np.abs(lost - heat)) < 1e-6 * lost[-1]


class Column(pdbfs.Rig):
    """A mass striking an oil column at V0: half a sine of compression,
    ``d = V0/w sin(w t)`` with ``w = sqrt(k_T/m)``; the oil's temperature
    from a FixedTemperature through the heat port, or the parameter T."""

    def __init__(self, law: str, port: bool, **kw):
        self._law, self._port = law, port
        super().__init__(**kw)

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=100.0, v0=1.0)
        self.oil = OilColumn(k=1e8, A=1e-2, stiffness_law=self._law, heat_port=self._port)
        self.connect(self.body.flange_b, self.oil.flange_a)
        self.connect(self.oil.flange_b, self.frame.flange)
        if self._port:
            self.bath = TH.FixedTemperature(T=293.15)
            self.connect(self.oil.heat_port, self.bath.port)


class TwoInOne(Oscillator):
    """The warm oscillator and, beside it, a mass striking an oil column whose
    stiffness law reads a bath's temperature: one FMU for both checks."""

    def declare(self):
        super().declare()
        self.striker = Mass(m=100.0, v0=1.0)
        self.oil = OilColumn(k=1e8, A=1e-2, stiffness_law="exponential", heat_port=True)
        self.bath = TH.FixedTemperature(T=293.15)
        self.connect(self.striker.flange_b, self.oil.flange_a)
        self.connect(self.oil.flange_b, self.frame.flange)
        self.connect(self.oil.heat_port, self.bath.port)


@pytest.fixture(scope="module")
def two_in_one_fmu(tmp_path_factory):
    return str(export_fmu(TwoInOne().compile(), tmp_path_factory.mktemp("fmu") / "two.fmu"))


@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_in_the_fmu_the_lost_energy_is_the_heat_and_the_law_holds(two_in_one_fmu, fmi_type):
    start = {"bath.T": 303.15, **({"solver.rtol": 1e-10} if fmi_type == "CoSimulation" else {})}
    r = fmpy.simulate_fmu(two_in_one_fmu, fmi_type=fmi_type, stop_time=3.0, output_interval=1e-5,
                          start_values=start, relative_tolerance=1e-10,
                          output=["body.s", "body.v", "heat.T", "oil.k_T", "oil.pressure"])
    lost, heat = _lost_and_heat(r["body.s"], r["body.v"], r["heat.T"])
    assert lost[-1] > 0.9 * 0.5 * M * V0 ** 2
    assert np.max(np.abs(lost - heat)) < 1e-6 * lost[-1]
    # 10 K warmer: k_T = k exp(-0.04), the peak sqrt(k_T m) v0 / A (on a 10 us grid:
    # within 1.3e-5 of the located peak)
    k_T = 1e8 * math.exp(-0.04)
    assert r["oil.k_T"][0] == pytest.approx(k_T, rel=1e-14)
    assert np.max(r["oil.pressure"]) == pytest.approx(math.sqrt(k_T * 100.0) / 1e-2, rel=2e-5)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("port", [True, False])
@pytest.mark.parametrize("law", ["linear", "exponential"])
def test_a_warmer_oil_column_gives_the_closed_form_frequency_shift(backend, law, port):
    """10 K warmer at 0.4 %/K: k_T = k (1 - 0.04) or k exp(-0.04); the peak
    pressure scales with sqrt(k_T), the time of the peak with 1/sqrt(k_T)."""
    where = "bath.T" if port else "oil.T"
    rig = Column(law, port)
    cold = rig.simulate(0.01, backend=backend, params={where: 293.15}, **TIGHT)
    hot = rig.simulate(0.01, backend=backend, params={where: 303.15}, **TIGHT)
    factor = 0.96 if law == "linear" else math.exp(-0.04)
    assert hot["oil.k_T"][0] == pytest.approx(1e8 * factor, rel=1e-14)
    (t_c, p_c), (t_h, p_h) = cold.peak("oil.pressure"), hot.peak("oil.pressure")
    w = math.sqrt(1e8 / 100.0)
    assert t_c == pytest.approx(math.pi / 2 / w, rel=1e-8)
    assert p_c == pytest.approx(1.0 * math.sqrt(1e8 * 100.0) / 1e-2, rel=1e-8)
    assert p_h / p_c == pytest.approx(math.sqrt(factor), rel=1e-8)
    assert t_h / t_c == pytest.approx(1 / math.sqrt(factor), rel=1e-8)


class Coasting(pdbfs.Rig):
    """A mass coasting against a viscous seal: v = V0 exp(-c_T t / m)."""

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=M, v0=V0)
        self.seal = SealFriction(c=4.0, viscosity_law="andrade")
        self.connect(self.frame.flange, self.seal.flange_a)
        self.connect(self.seal.flange_b, self.body.flange_a)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_warmer_seal_follows_andrades_viscosity(backend):
    B_ = TH.WATER_GLYCOL_ANDRADE_B
    res = Coasting().simulate(1.0, n_out=101, backend=backend, params={"seal.T": 303.15}, **TIGHT)
    c_T = 4.0 * math.exp(B_ * (1 / 303.15 - 1 / 293.15))
    assert 0.65 < c_T / 4.0 < 0.75                     # about -30 % per 10 K near 20 degC
    assert res["seal.c_T"][0] == pytest.approx(c_T, rel=1e-14)
    np.testing.assert_allclose(res["body.v"], V0 * np.exp(-c_T * res.t / M), rtol=1e-8)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_law_switched_off_changes_nothing(backend):
    """alpha_T = 0: the factor is exactly 1, the run the same to the last bit
    as the column without a law."""
    plain = Column(None, False).simulate(0.01, backend=backend)
    off = Column("exponential", False).simulate(0.01, backend=backend,
                                                params={"oil.alpha_T": 0.0, "oil.T": 350.0})
    for name in ("body.s", "body.v", "oil.pressure"):
        np.testing.assert_array_equal(off[name], plain[name])


def test_without_a_heat_port_a_component_has_none():
    for comp in (Damper(), SealFriction(), ImpactContact(), OilColumn(), H.Orifice(),
                 H.LaminarLeak(), H.CheckValve()):
        assert "heat_port" not in comp._connectors and "loss_power" not in comp._vars
    for comp in (Damper(heat_port=True), SealFriction(heat_port=True), H.CheckValve(heat_port=True),
                 ImpactContact(heat_port=True), OilColumn(heat_port=True)):
        assert "heat_port" in comp._connectors and "loss_power" in comp._vars


@pytest.mark.parametrize("make", [lambda: OilColumn(stiffness_law="cubic"),
                                  lambda: SealFriction(viscosity_law="vogel"),
                                  lambda: Damper(heat_port="no")])
def test_an_unknown_law_or_flag_is_refused_in_one_line(make):
    with pytest.raises(ParameterError) as err:
        make()
    assert "\n" not in str(err.value)
