"""Calibration: parameters recovered from traces made with pdbfs itself (noise,
trigger shift, sensor offset), within the uncertainty the fit reports;
parameters a trace cannot determine reported as such."""
import numpy as np
import pytest

import pdbfs
from pdbfs.components import Fixed, Force, Mass, Spring
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.studies.fitting.signal_model import SignalModel

TRUE = {"oil.k": 3.1e8, "seal.c": 6.0e4, "hammer.v0": 3.2}
NOISE = 0.5e6   # Pa, about 0.4 % of the peak


def noisy_trace(params, t, shift=0.0, offset=0.0, seed=1):
    """The rig's pressure at t - shift (at rest before 0), plus offset and noise."""
    rig = paper_rig()
    tm = np.round(np.clip(t - shift, 0.0, None), 12)     # no 1e-19 s steps from rounding
    grid = np.unique(np.concatenate([[0.0], tm[tm > 0]]))
    res = rig.simulate(t_out=grid, params=params, rtol=1e-10, atol=1e-12)
    y = np.interp(tm, grid, res["oil.pressure"])
    return y + offset + np.random.default_rng(seed).normal(0.0, NOISE, t.size)


def within(cal, truth, k=4.0):
    for name, v in truth.items():
        assert cal.params[name] is not None, name
        assert abs(cal.params[name] - v) < k * cal.std[name], (name, cal.params[name], v, cal.std[name])


def test_the_signal_model_interpolates_the_solution_and_its_sensitivities():
    rig = paper_rig()
    sim = Simulator.of(rig)
    m = SignalModel(sim, "oil.pressure", ["oil.k"], 0.014, sim.param_vector())
    s = m([2.228e8])
    times = np.array([0.0013371, 0.0047773, 0.0091234, 0.0123457])   # off the 5 us grid
    y, ydot, dy = s.at(times)
    res = rig.simulate(t_out=np.concatenate([[0.0], times]), rtol=1e-10, atol=1e-12)
    assert np.allclose(y, res["oil.pressure"][1:], rtol=0, atol=2e-6 * res["oil.pressure"].max())
    h = 1e-3 * 2.228e8
    fd = (m([2.228e8 + h], sens=False).at(times)[0] - m([2.228e8 - h], sens=False).at(times)[0]) / (2 * h)
    assert np.allclose(dy[:, 0], fd, rtol=2e-3, atol=1e-4 * np.abs(fd).max())
    assert s.at([-1e-3])[0][0] == s.y[0] and s.at([-1e-3])[1][0] == 0.0   # at rest before impact


def test_three_parameters_recovered_from_a_noisy_trace():
    t = np.linspace(0.0, 0.016, 801)                  # 20 us sampling
    cal = pdbfs.calibrate(paper_rig(), (t, noisy_trace(TRUE, t)), ["oil.k", "seal.c", "hammer.v0"])
    within(cal, TRUE)
    assert not cal.undetermined
    assert 0.85 * NOISE < cal.rms_residual < 1.15 * NOISE       # fits down to the noise
    assert cal.corr["oil.k"]["oil.k"] == pytest.approx(1.0)
    d = cal.to_dict()
    assert set(d["params"]) == set(d["std"]) == set(TRUE) and d["rms_residual"] > 0
    # plain floats, as printed (hammer.v0, scaled linearly, was np.float64(...))
    assert all(type(v) is float for v in cal.params.values()), cal.params
    assert "np." not in repr(d)


def test_trigger_shift_and_sensor_offset_recovered():
    t = np.arange(0.0, 0.017, 1e-5)
    shift, offset = 1.2e-3, 0.3e6
    y = noisy_trace(TRUE, t, shift, offset, seed=2)
    cal = pdbfs.calibrate("paper", (t, y), "oil.k,seal.c,hammer.v0", fit_offset=True)
    within(cal, {**TRUE, "trace.shift": shift, "trace.offset": offset})
    assert cal.rms_residual < 1.15 * NOISE


def test_a_parameter_the_trace_does_not_feel_is_not_made_up():
    """Table 1's hysteresis damping D barely touches the pressure: the fit
    says so and holds it, instead of returning a number."""
    t = np.linspace(0.0, 0.014, 351)
    truth = {"oil.k": 3.1e8, "seal.c": 6.0e4}
    cal = pdbfs.calibrate(paper_rig(), (t, noisy_trace(truth, t, seed=3)),
                          ["oil.k", "seal.c", "contact.D"], starts=1)
    assert cal.params["contact.D"] is None and cal.std["contact.D"] is None
    assert "contact.D" in cal.undetermined and cal.held["contact.D"] == 1.595e6
    within(cal, truth)


class Oscillator(pdbfs.Rig):
    """A mass on a spring pushed by a constant force: its motion
    x = F/k (1 - cos(sqrt(k/m) t)) shows F/k and k/m, never F, k and m alone."""

    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=4e4)
        self.body = Mass(m=2.0)
        self.push = Force(F=100.0)
        self.connect(self.frame.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.body.flange_a)
        self.connect(self.body.flange_b, self.push.flange)


def test_entangled_parameters_are_named_and_the_rest_still_fitted():
    rig = Oscillator()
    t = np.linspace(0.0, 0.1, 201)
    res = rig.simulate(t_out=t, params={"spring.k": 5e4, "push.F": 150.0}, rtol=1e-10)
    y = res["body.s"] + np.random.default_rng(4).normal(0.0, 1e-5, t.size)
    free = ["spring.k", "push.F", "body.m"]
    cal = pdbfs.calibrate(rig, (t, y), free, signal="body.s", starts=1)
    (held, why), = cal.undetermined.items()
    assert cal.params[held] is None and all(n in why for n in set(free) - {held})
    v = {**cal.held, **{n: x for n, x in cal.params.items() if x is not None}}
    assert v["push.F"] / v["spring.k"] == pytest.approx(150.0 / 5e4, rel=1e-3)
    assert v["spring.k"] / v["body.m"] == pytest.approx(5e4 / 2.0, rel=1e-3)
    assert cal.rms_residual < 1.2e-5
