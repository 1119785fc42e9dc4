"""The thermal domain against closed forms, on both back ends: Newton cooling
of a capacitor through a conductor and through convection (its conductance
a parameter or a signal), two capacitors sharing heat, heat flow and
temperature sources, the sensors; an unconnected heat port refused in one
line where heat would have nowhere to go."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.components import blocks as B
from pdbfs.components import thermal as TH
from pdbfs.errors import ConnectError, ParameterError

BACKENDS = ["c", "casadi"]
TIGHT = dict(rtol=1e-10, atol=1e-12)
C, G, T0, TA = 500.0, 2.0, 350.0, 290.0        # J/K, W/K, K, K: tau = 250 s


class Cooling(pdbfs.Rig):
    """A capacitor losing heat to an ambient at TA through ``link`` (a
    ThermalConductor or a Convection), a sensor on its temperature and one
    in series on the heat it loses."""

    def __init__(self, link: str = "conductor", **kw):
        self._link = link
        super().__init__(**kw)

    def declare(self):
        self.body = TH.HeatCapacitor(C=C, T0=T0)
        self.ambient = TH.FixedTemperature(T=TA)
        self.temp = TH.TemperatureSensor()
        self.flow = TH.HeatFlowSensor()
        if self._link == "conductor":
            self.link = TH.ThermalConductor(G=G)
            a, b = self.link.port_a, self.link.port_b
        else:
            signal = self._link == "convection-signal"
            self.link = TH.Convection(use_input=signal) if signal else TH.Convection(Gc=G)
            a, b = self.link.solid, self.link.fluid
            if signal:
                self.gc = B.Constant(unit="W/K", k=G)
                self.connect(self.gc.y, self.link.Gc)
        self.connect(self.body.port, a, self.temp.port)
        self.connect(b, self.flow.port_a)
        self.connect(self.flow.port_b, self.ambient.port)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("link", ["conductor", "convection", "convection-signal"])
def test_newton_cooling(backend, link):
    """T(t) = TA + (T0 - TA) exp(-G t / C); the heat lost is C (T0 - T)."""
    res = Cooling(link).simulate(1000.0, n_out=401, backend=backend, **TIGHT)
    want = TA + (T0 - TA) * np.exp(-G * res.t / C)
    assert np.max(np.abs(res["body.T"] - want)) < 1e-8 * (T0 - TA)
    np.testing.assert_array_equal(res["temp.y"], res["body.T"])
    np.testing.assert_allclose(res["flow.y"], G * (res["body.T"] - TA), rtol=1e-12)
    assert res["link.Q_flow"][0] == pytest.approx(G * (T0 - TA), rel=1e-12)


class TwoBodies(pdbfs.Rig):
    """Two insulated capacitors joined by a conductor; a heater in the first."""

    def __init__(self, heat: float = 0.0, **kw):
        self._heat = heat
        super().__init__(**kw)

    def declare(self):
        self.hot = TH.HeatCapacitor(C=300.0, T0=400.0)
        self.cold = TH.HeatCapacitor(C=900.0, T0=300.0)
        self.wall = TH.ThermalConductor(G=3.0)
        self.heater = TH.FixedHeatFlow(Q_flow=self._heat)
        self.connect(self.hot.port, self.wall.port_a, self.heater.port)
        self.connect(self.wall.port_b, self.cold.port)


@pytest.mark.parametrize("backend", BACKENDS)
def test_two_bodies_share_their_heat(backend):
    """The difference decays with the rate G (1/C1 + 1/C2); the heat is conserved."""
    res = TwoBodies().simulate(500.0, n_out=201, backend=backend, **TIGHT)
    rate = 3.0 * (1 / 300.0 + 1 / 900.0)
    diff = res["hot.T"] - res["cold.T"]
    assert np.max(np.abs(diff - 100.0 * np.exp(-rate * res.t))) < 1e-8 * 100.0
    energy = 300.0 * res["hot.T"] + 900.0 * res["cold.T"]
    assert np.max(np.abs(energy - energy[0])) < 1e-9 * energy[0]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_heater_raises_the_mean_temperature_linearly(backend):
    """With Q W in, the heat-weighted mean rises by Q t / (C1 + C2)."""
    res = TwoBodies(heat=60.0).simulate(500.0, n_out=201, backend=backend, **TIGHT)
    mean = (300.0 * res["hot.T"] + 900.0 * res["cold.T"]) / 1200.0
    assert np.max(np.abs(mean - (325.0 + 60.0 * res.t / 1200.0))) < 1e-9 * 325.0


class Driven(pdbfs.Rig):
    """A capacitor behind a conductor from a PrescribedTemperature that
    ramps, and heated by a PrescribedHeatFlow that steps."""

    def declare(self):
        self.body = TH.HeatCapacitor(C=C, T0=T0)
        self.link = TH.ThermalConductor(G=G)
        self.source = TH.PrescribedTemperature()
        self.ramp = B.Ramp(unit="K", offset=T0, height=50.0, duration=1e4)
        self.heater = TH.PrescribedHeatFlow()
        self.step = B.Step(unit="W", height=20.0, start_time=100.0)
        self.connect(self.ramp.y, self.source.u)
        self.connect(self.step.y, self.heater.u)
        self.connect(self.source.port, self.link.port_a)
        self.connect(self.link.port_b, self.body.port, self.heater.port)


@pytest.mark.parametrize("backend", BACKENDS)
def test_prescribed_sources_give_the_first_order_response(backend):
    """A ramp of rate r behind a lag tau = C/G: T = T0 + r (t - tau (1 - e^(-t/tau)));
    a step of heat Q from t1 adds Q/G (1 - e^(-(t - t1)/tau))."""
    res = Driven().simulate(1000.0, n_out=501, backend=backend, **TIGHT)
    tau, r, t = C / G, 50.0 / 1e4, res.t
    want = T0 + r * (t - tau * (1 - np.exp(-t / tau)))
    want += np.where(t >= 100.0, 20.0 / G * (1 - np.exp(-(t - 100.0) / tau)), 0.0)
    assert np.max(np.abs(res["body.T"] - want)) < 1e-8 * 10.0


def test_an_unconnected_capacitor_is_insulated():
    class Alone(pdbfs.Rig):
        def declare(self):
            self.body = TH.HeatCapacitor(C=C, T0=T0)
            self.heater = TH.FixedHeatFlow(Q_flow=5.0)
            self.connect(self.body.port, self.heater.port)
            self.spare = TH.HeatCapacitor(C=1.0, T0=TA)

    res = Alone().simulate(100.0, n_out=11)
    np.testing.assert_allclose(res["body.T"], T0 + 5.0 * res.t / C, rtol=1e-12)
    assert np.all(res["spare.T"] == TA)


@pytest.mark.parametrize("make", [TH.TemperatureSensor, TH.FixedHeatFlow, TH.PrescribedHeatFlow])
def test_a_port_that_cannot_be_insulated_is_refused_in_one_line(make):
    class Loose(pdbfs.Rig):
        def declare(self):
            self.part = make()
            if make is TH.PrescribedHeatFlow:
                self.q = B.Constant(unit="W", k=1.0)
                self.connect(self.q.y, self.part.u)

    with pytest.raises(ConnectError) as err:
        Loose().compile()
    msg = str(err.value)
    assert "part.port" in msg and "not connected" in msg and "\n" not in msg


def test_every_thermal_parameter_has_a_unit_and_a_description():
    for name in TH.__all__:
        cls = getattr(TH, name)
        if not (isinstance(cls, type) and issubclass(cls, pdbfs.Component)) or \
                name.startswith("Partial"):
            continue
        comp = cls()
        for p in comp._params.values():
            assert p.decl.unit and len(p.decl.description) > 10, (name, p.name)
        for c in comp._connectors.values():
            for _, _, unit, desc, _ in c.variables():
                assert unit and desc, (name, c.name)


def test_convection_takes_its_conductance_as_a_parameter_or_a_signal():
    assert "Gc" in TH.Convection()._params
    conv = TH.Convection(use_input=True)
    assert "Gc" not in conv._params and "Gc" in conv._connectors
    with pytest.raises(ParameterError, match="use_input"):
        TH.Convection(use_input="yes")


def test_the_laws_are_one_at_the_reference_and_follow_their_closed_forms():
    assert TH.linear_factor(300.0, 300.0, 4e-3) == 1.0
    assert TH.exponential_factor(300.0, 300.0, 4e-3) == 1.0
    assert TH.andrade_factor(300.0, 300.0, 3000.0) == 1.0
    assert TH.exponential_factor(310.0, 300.0, 0.0) == TH.andrade_factor(310.0, 300.0, 0.0) == 1.0
    assert TH.linear_factor(310.0, 300.0, 4e-3) == pytest.approx(0.96, rel=1e-15)
    assert TH.exponential_factor(310.0, 300.0, 4e-3) == pytest.approx(math.exp(-0.04), rel=1e-15)
    # Andrade through two data points returns the ratio of the viscosities there
    (t1, nu1), (t2, nu2) = TH.WATER_GLYCOL_VISCOSITY
    B_ = TH.andrade_constant(t1, nu1, t2, nu2)
    assert B_ == TH.WATER_GLYCOL_ANDRADE_B
    assert TH.andrade_factor(t2, t1, B_) == pytest.approx(nu2 / nu1, rel=1e-13)
    with pytest.raises(ValueError, match="T1 and T2"):
        TH.andrade_constant(300.0, 1.0, 300.0, 2.0)
