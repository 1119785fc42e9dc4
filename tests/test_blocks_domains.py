"""Signals joined to the physical domains, against closed forms: a
mass-spring-damper pushed through SignalForce by a Step, a Sine and an
Input (the full response, transient included), a position loop closed
through a PositionSensor's ``y``, SignalPosition, a volume filled through a
CommandedValve against the fixed Orifice, SignalPressure through a laminar
leak; and the sensors' ``y`` outputs. Both back ends."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.components import (Damper, Fixed, ForceSensor, Mass, PositionSensor, PressureSensor,
                              SignalForce, SignalPosition, SpeedSensor, Spring)
from pdbfs.components import blocks as B
from pdbfs.components import hydraulic as H

from input_rigs import BACKENDS, TIGHT, C, K, M, Pushed, msd_sine, msd_step


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_step_force_gives_the_step_response(backend):
    rig = Pushed(B.Step(unit="N", height=10.0, start_time=0.1))
    res = rig.simulate(1.5, n_out=1501, backend=backend, **TIGHT)
    want = msd_step(res.t, 10.0, 0.1)
    assert np.max(np.abs(res["pos.y"] - want)) < 1e-7 * (10.0 / K)
    assert np.array_equal(res["push.force"], np.where(res.t >= 0.1, 10.0, 0.0))
    assert list(rig.compile().time_event_times(rig.compile().p_default())) == [0.1]


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("phase", [0.0, 1.1])       # 1.1 rad: the force jumps at the start
def test_a_sine_force_gives_the_full_sine_response(backend, phase):
    rig = Pushed(B.Sine(unit="N", amplitude=5.0, f=2.5, phase=phase, start_time=0.05))
    res = rig.simulate(2.0, n_out=2001, backend=backend, **TIGHT)
    want = msd_sine(res.t, 5.0, 2.5, phase, 0.05)
    scale = np.max(np.abs(want))
    assert scale > 5.0 / K                             # transient and forced parts both there
    assert np.max(np.abs(res["body.s"] - want)) < 1e-7 * scale


@pytest.mark.parametrize("backend", BACKENDS)
def test_an_input_drives_the_rig_at_its_start_value(backend):
    rig = Pushed(B.Input("N", start=3.0, description="Force command"))
    assert rig.u.input_name() == "u" and rig.u.rig_input
    info = rig.compile().inputs[0]
    assert (info.name, info.start, info.unit) == ("u", 3.0, "N")
    assert "Force command" in info.description
    res = rig.simulate(1.0, n_out=501, backend=backend, **TIGHT)
    assert np.max(np.abs(res["pos.y"] - msd_step(res.t, 3.0, 0.0))) < 1e-7 * (3.0 / K)
    res = rig.simulate(1.0, n_out=501, inputs={"u": 8.0}, backend=backend, **TIGHT)
    assert np.max(np.abs(res["pos.y"] - msd_step(res.t, 8.0, 0.0))) < 1e-7 * (8.0 / K)


def test_the_rig_linearized_in_its_input_is_the_mass_spring_damper():
    """B and D with respect to the Input: the force enters der(v) as 1/m;
    the transfer function to the position is 1/(m s^2 + c s + k)."""
    lin = Pushed(B.Input("N")).linearize(inputs=["u"], outputs=["pos.y"])
    order = [lin.states.index("body.s"), lin.states.index("body.v")]
    A = lin.A[np.ix_(order, order)]
    assert np.allclose(A, [[0.0, 1.0], [-K / M, -C / M]], rtol=1e-12, atol=0)
    assert np.allclose(lin.B[order, 0], [0.0, 1.0 / M], rtol=1e-12, atol=0)
    assert np.allclose(lin.C[0, order], [1.0, 0.0]) and lin.D[0, 0] == 0.0
    s = 2j * math.pi * 3.0
    G = (lin.C[:, order] @ np.linalg.solve(s * np.eye(2) - A, lin.B[order]))[0, 0]
    assert G == pytest.approx(1.0 / (M * s * s + C * s + K), rel=1e-12)


class PositionLoop(pdbfs.Rig):
    """A damped mass held at a setpoint by a P controller on its measured
    position: m x'' + c x' = kp*(r - x), the spring-damper's step response
    with k = kp."""

    def declare(self):
        self.frame = Fixed()
        self.damper = Damper(c=C)
        self.body = Mass(m=M)
        self.pos = PositionSensor()
        self.setpoint = B.Step(unit="m", height=0.02, start_time=0.0)
        self.error = B.Add(unit="m", k2=-1.0)
        self.control = B.PID(kind="P", k=K, unit="N", input_unit="m")
        self.push = SignalForce()
        self.connect(self.frame.flange, self.damper.flange_a)
        self.connect(self.damper.flange_b, self.body.flange_a, self.pos.flange)
        self.connect(self.body.flange_b, self.push.flange)
        self.connect(self.setpoint.y, self.error.u1)
        self.connect(self.pos.y, self.error.u2)
        self.connect(self.error.y, self.control.u)
        self.connect(self.control.y, self.push.u)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_position_loop_through_the_sensors_output(backend):
    res = PositionLoop().simulate(1.5, n_out=751, backend=backend, **TIGHT)
    want = msd_step(res.t, K * 0.02, 0.0)
    assert np.max(np.abs(res["body.s"] - want)) < 1e-7 * 0.02
    assert np.allclose(res["control.y"], K * (0.02 - res["body.s"]), rtol=0, atol=1e-9)


class Shaken(pdbfs.Rig):
    """A body moved by SignalPosition along y = a*(cos(w t) - 1), on a
    spring to the frame."""

    def declare(self):
        self.src = B.Sine(unit="m", amplitude=0.01, f=5.0, phase=math.pi / 2, offset=-0.01)
        self.drive = SignalPosition()
        self.body = Mass(m=2.0)
        self.spring = Spring(k=1e3)
        self.frame = Fixed()
        self.connect(self.src.y, self.drive.u)
        self.connect(self.drive.flange, self.body.flange_a)
        self.connect(self.body.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.frame.flange)


@pytest.mark.parametrize("backend", ["casadi", "c"])
def test_signal_position_prescribes_the_motion(backend):
    res = Shaken().simulate(0.5, n_out=101, backend=backend)
    w, t = 2 * math.pi * 5.0, None
    t = res.t
    s = 0.01 * (np.cos(w * t) - 1)
    assert np.allclose(res["body.s"], s, rtol=0, atol=1e-14)
    assert np.allclose(res["body.a"], -0.01 * w * w * np.cos(w * t), rtol=0, atol=1e-11)
    # the drive supplies the body's inertia and the spring's pull: f = -(m a + k s)
    assert np.allclose(res["drive.flange.f"], -(2.0 * res["body.a"] + 1e3 * s), rtol=0, atol=1e-10)


class Filling(pdbfs.Rig):
    """A sealed chamber filled from a 10 MPa supply through a valve: a
    CommandedValve opened by ``command`` (a block), or a fixed Orifice of
    area ``area`` (command None)."""

    def __init__(self, command=None, area=1e-6, **kw):
        self._command, self._area = command, area
        super().__init__(**kw)

    def declare(self):
        self.supply = H.PressureSource(p=10e6)
        self.chamber = H.Volume(V=1e-3, K=1.5e9, p0=1e5)
        self.sensor = H.PressureSensor()
        if self._command is None:
            self.valve = H.Orifice(A=self._area, dp_t=10.0)
        else:
            self.valve = H.CommandedValve(A=1e-6, dp_t=10.0)
            self.command = self._command
            self.connect(self.command.y, self.valve.opening)
        self.connect(self.supply.port, self.valve.port_a)
        self.connect(self.valve.port_b, self.chamber.port, self.sensor.port)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("opening", [0.4, 1.7])      # 1.7: held at the open stop, area A
def test_a_commanded_valve_at_a_fixed_opening_is_the_orifice(backend, opening):
    got = Filling(B.Constant(k=opening)).simulate(0.05, n_out=501, backend=backend, **TIGHT)
    ref = Filling(area=min(opening, 1.0) * 1e-6).simulate(0.05, n_out=501, backend=backend,
                                                           **TIGHT)
    p = ref["chamber.p"]
    assert p[-1] > 2e6                                 # it fills well on the way
    assert np.max(np.abs(got["sensor.y"] - p)) < 1e-8 * p.max()
    assert np.allclose(got["valve.q"], ref["valve.q"], rtol=1e-6, atol=1e-9 * ref["valve.q"].max())


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_closed_commanded_valve_passes_nothing_until_it_opens(backend):
    """Closed (command 0, on the stop) until 0.02 s, then opened to 0.4: the
    fixed orifice's filling, shifted by 0.02 s."""
    t1 = 0.02
    got = Filling(B.Step(height=0.4, start_time=t1)).simulate(0.07, n_out=701, backend=backend,
                                                              **TIGHT)
    ref = Filling(area=0.4e-6).simulate(0.05, n_out=501, backend=backend, **TIGHT)
    # before the switch nothing flows; at it the state is continuous (to the
    # solver's tolerance: the step ending there may see the new value in its
    # last stage)
    before = got.t < t1
    assert np.all(got["chamber.p"][before] == pytest.approx(1e5, rel=1e-12))
    after = got.t >= t1
    assert np.max(np.abs(got["chamber.p"][after] - ref["chamber.p"])) < 1e-8 * 10e6


class Leaking(pdbfs.Rig):
    """A chamber (no cavitation clamp) fed through a laminar leak by
    SignalPressure driven by a step."""

    def declare(self):
        self.step = B.Step(unit="Pa", offset=1e5, height=5e6, start_time=0.01)
        self.source = H.SignalPressure()
        self.leak = H.LaminarLeak(G=2e-12)
        self.chamber = H.Volume(V=1e-3, K=1.5e9, p0=1e5, cavitation=False)
        self.connect(self.step.y, self.source.u)
        self.connect(self.source.port, self.leak.port_a)
        self.connect(self.leak.port_b, self.chamber.port)


@pytest.mark.parametrize("backend", BACKENDS)
def test_signal_pressure_fills_through_a_leak_exponentially(backend):
    res = Leaking().simulate(0.05, n_out=501, backend=backend, **TIGHT)
    tau = 1e-3 / (1.5e9 * 2e-12)                       # V/(K G) = 1/3 s
    want = 1e5 + 5e6 * (1 - np.exp(-np.clip(res.t - 0.01, 0, None) / tau))
    assert np.max(np.abs(res["chamber.p"] - want)) < 1e-7 * 5e6
    assert np.allclose(res["source.q_out"], 2e-12 * (res["source.port.p"] - res["chamber.p"]),
                       rtol=1e-12, atol=1e-22)


class Instrumented(pdbfs.Rig):
    """A mass pushed by a ramp through a force and a pressure sensor, with
    position and speed sensors on it."""

    def declare(self):
        self.body = Mass(m=2.0)
        self.pos = PositionSensor()
        self.speed = SpeedSensor()
        self.load = ForceSensor()
        self.gauge = PressureSensor(A=1e-3)
        self.ramp = B.Ramp(unit="N", height=50.0, duration=1.0)
        self.push = SignalForce()
        self.connect(self.body.flange_a, self.pos.flange, self.speed.flange)
        self.connect(self.body.flange_b, self.load.flange_a)
        self.connect(self.load.flange_b, self.gauge.flange_a)
        self.connect(self.gauge.flange_b, self.push.flange)
        self.connect(self.ramp.y, self.push.u)


def test_the_sensors_give_their_reading_as_y_too():
    res = Instrumented().simulate(1.0, n_out=101, **TIGHT)
    t = res.t
    assert np.allclose(res["pos.y"], 50.0 / 2.0 * t ** 3 / 6, rtol=1e-8, atol=1e-14)
    for name, own in (("pos", "s"), ("speed", "v"), ("load", "f"), ("gauge", "p")):
        assert np.array_equal(res[f"{name}.y"], res[f"{name}.{own}"]), name
    assert np.allclose(res["speed.y"], 50.0 / 2.0 * t ** 2 / 2, rtol=1e-8, atol=1e-14)
    assert np.allclose(res["load.y"], 50.0 * t, rtol=1e-12, atol=1e-12)   # tension, as before
    assert np.allclose(res["gauge.y"], -50.0 * t / 1e-3, rtol=1e-12, atol=1e-9)
    assert np.array_equal(res["gauge.f"], res["load.f"])                   # still the force
    dae = Instrumented().compile()
    units = {v.name: v.unit for v in dae.y_info}
    assert (units["pos.y"], units["speed.y"], units["load.y"], units["gauge.y"]) == \
        ("m", "m/s", "N", "Pa")


def test_the_hydraulic_sensors_give_their_reading_as_y_too():
    class R(pdbfs.Rig):
        def declare(self):
            self.supply = H.PressureSource(p=5e6)
            self.flow = H.FlowSensor()
            self.leak = H.LaminarLeak(G=1e-11)
            self.tank = H.Tank(p=1e5)
            self.gauge = H.PressureSensor()
            self.connect(self.supply.port, self.flow.port_a, self.gauge.port)
            self.connect(self.flow.port_b, self.leak.port_a)
            self.connect(self.leak.port_b, self.tank.port)
    res = R().simulate(0.01, n_out=3, backend="casadi")
    assert np.allclose(res["gauge.y"], 5e6) and np.array_equal(res["gauge.y"], res["gauge.p"])
    assert np.allclose(res["flow.y"], 1e-11 * (5e6 - 1e5)) and \
        np.array_equal(res["flow.y"], res["flow.q"])
