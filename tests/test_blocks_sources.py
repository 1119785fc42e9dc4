"""The signal sources and static blocks against their formulas: pointwise on
the output grid, and integrated (an Integrator downstream), where a switch
that the solver stepped over would show. Every switch is a time event: a
pulse far shorter than the solver's steps is never missed (without the
events both back ends step over it and integrate nothing)."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.components import blocks as B

BACKENDS = ["c", "casadi"]
TIGHT = dict(rtol=1e-10, atol=1e-12)


class Integrated(pdbfs.Rig):
    """``source`` and its integral (an Integrator, so that the rig has a
    state and both back ends run it)."""

    def __init__(self, source, **kw):
        self._source = source
        super().__init__(**kw)

    def declare(self):
        self.src = self._source
        self.integral = B.Integrator()
        self.connect(self.src.y, self.integral.u)


def run(source, t_end, backend, n_out=1001, **settings):
    rig = Integrated(source)
    return rig, rig.simulate(t_end, n_out=n_out, backend=backend, **(settings or TIGHT))


@pytest.mark.parametrize("backend", BACKENDS)
def test_step_and_ramp(backend):
    _, res = run(B.Step(height=2.5, offset=-1.0, start_time=0.3), 1.0, backend)
    t = res.t
    assert np.array_equal(res["src.y"], np.where(t >= 0.3, 1.5, -1.0))
    want = -t + 2.5 * np.clip(t - 0.3, 0, None)
    assert np.max(np.abs(res["integral.y"] - want)) < 1e-9
    _, res = run(B.Ramp(height=3.0, duration=0.4, offset=0.5, start_time=0.2), 1.0, backend)
    x = np.clip((t - 0.2) / 0.4, 0, 1)
    assert np.allclose(res["src.y"], 0.5 + 3.0 * x, rtol=0, atol=1e-15)
    # integral of the ramp: 0.5 t + the area under the rising part and the hold
    area = np.where(t < 0.6, 3.0 * 0.4 * x ** 2 / 2, 3.0 * 0.2 + 3.0 * (t - 0.6))
    assert np.max(np.abs(res["integral.y"] - (0.5 * t + area))) < 1e-9


@pytest.mark.parametrize("backend", BACKENDS)
def test_sine_from_its_start_time(backend):
    A, f, ph, ts = 1.5, 3.0, 0.7, 0.1
    _, res = run(B.Sine(amplitude=A, f=f, phase=ph, offset=0.25, start_time=ts), 1.0, backend)
    t, w = res.t, 2 * math.pi * f
    on = t >= ts
    assert np.allclose(res["src.y"], 0.25 + np.where(on, A * np.sin(w * (t - ts) + ph), 0.0),
                       rtol=0, atol=1e-14)
    want = 0.25 * t + np.where(on, A / w * (math.cos(ph) - np.cos(w * (t - ts) + ph)), 0.0)
    assert np.max(np.abs(res["integral.y"] - want)) < 1e-7 * A / w


def pulse(t, amplitude, width, period, start, periods, offset=0.0):
    k = np.floor((t - start) / period)
    high = (t >= start) & (k < periods) & (t - start - k * period < width)
    return offset + amplitude * high


@pytest.mark.parametrize("backend", BACKENDS)
def test_pulse_train_and_its_bound(backend):
    """Five pulses of 30 ms every 100 ms from 50 ms; then the train ends."""
    src = B.Pulse(periods=5, amplitude=2.0, width=0.03, period=0.1, start_time=0.05, offset=0.5)
    rig, res = run(src, 1.0, backend, n_out=2001)
    dae = rig.compile()
    edges = np.sort(np.concatenate([0.05 + 0.1 * np.arange(5), 0.08 + 0.1 * np.arange(5)]))
    assert dae.time_event_times(dae.p_default()) == pytest.approx(edges, abs=1e-15)
    t = res.t
    clear = np.min(np.abs(t[:, None] - edges[None, :]), axis=1) > 1e-12   # grid points on a
    assert np.sum(~clear) == 10                                          # switch: rounding decides
    assert np.array_equal(res["src.y"][clear], pulse(t, 2.0, 0.03, 0.1, 0.05, 5, 0.5)[clear])
    done = np.minimum(np.clip(t - 0.05, 0, None), 0.5)
    full, part = np.floor(done / 0.1), done - np.floor(done / 0.1) * 0.1
    want = 0.5 * t + 2.0 * (full * 0.03 + np.minimum(part, 0.03))
    assert np.max(np.abs(res["integral.y"] - want)) < 1e-9
    assert res["integral.y"][-1] == pytest.approx(0.5 + 2.0 * 5 * 0.03, rel=1e-9)


@pytest.mark.parametrize("backend", BACKENDS)
def test_short_pulses_are_never_stepped_over(backend):
    """Pulses of 0.1 ms in a run of 1 s, three output points, default
    tolerances: each switch is a time event, so each pulse is integrated."""
    pulses = B.Pulse(periods=3, amplitude=1.0, width=1e-4, period=0.3, start_time=0.05)
    blip = B.Table([0.0, 0.5, 0.5001], [0.0, 1.0, 0.0], interpolation="hold")
    for src, area in ((pulses, 3e-4), (blip, 1e-4)):
        _, res = run(src, 1.0, backend, n_out=3, rtol=1e-8, atol=1e-10)
        assert res["integral.y"][-1] == pytest.approx(area, rel=1e-5)


TIMES = [0.1, 0.3, 0.35, 0.7]
VALUES = [1.0, -2.0, 0.5, 3.0]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_linear_table_is_numpy_interp(backend):
    _, res = run(B.Table(TIMES, VALUES), 1.0, backend)
    t = res.t
    assert np.allclose(res["src.y"], np.interp(t, TIMES, VALUES), rtol=0, atol=1e-15)
    # the integral: trapezoids between the breakpoints, the end values held outside
    fine = np.linspace(0, 1.0, 200001)
    trapz = np.concatenate([[0.0], np.cumsum(np.diff(fine) * 0.5 * (
        np.interp(fine[1:], TIMES, VALUES) + np.interp(fine[:-1], TIMES, VALUES)))])
    assert np.max(np.abs(res["integral.y"] - np.interp(t, fine, trapz))) < 1e-9


def held(t, times, values):
    i = np.searchsorted(times, t, side="right") - 1
    return np.asarray(values)[np.clip(i, 0, None)]


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_held_table_jumps_at_its_breakpoints(backend):
    rig, res = run(B.Table(TIMES, VALUES, interpolation="hold"), 1.0, backend, n_out=11)
    dae = rig.compile()
    assert list(dae.time_event_times(dae.p_default())) == TIMES
    t = res.t
    assert np.array_equal(res["src.y"], held(t, TIMES, VALUES))     # at 0.1, 0.3, 0.7: new values
    # the integral: the levels times the intervals, to the solver's tolerance
    # (the step ending at a switch sees the new value in its last evaluation)
    steps = np.diff(np.concatenate([[0.0], TIMES, [1.0]]))
    levels = np.concatenate([[VALUES[0]], VALUES])
    assert res["integral.y"][-1] == pytest.approx(np.dot(steps, levels), rel=1e-9)


@pytest.mark.parametrize("times, values, culprit", [
    ([0.0, 0.2, 0.1], [1, 2, 3], "times[2] = 0.10000000000000001 s is not after times[1]"),
    ([0.0, 0.2, 0.2], [1, 2, 3], "times[2] = 0.20000000000000001 s is not after times[1]"),
    ([0.0, float("nan")], [1, 2], "times[1] = nan"),
    ([0.0, 1.0], [1, float("inf")], "values[1] = inf"),
    ([0.0, 1.0], [1, 2, 3], "2 times but 3 values"),
    ([], [], "at least one number"),
    ("abc", [1], "times must be a sequence of numbers"),
    ([[0.0, 1.0]], [[1, 2]], "flat sequence"),
])
def test_a_bad_table_is_refused_in_one_line(times, values, culprit):
    with pytest.raises(pdbfs.ParameterError) as err:
        B.Table(times, values)
    assert culprit in str(err.value) and "\n" not in str(err.value)


def test_a_table_says_which_interpolations_there_are():
    with pytest.raises(pdbfs.ParameterError, match="'cubic'; choose one of linear, hold"):
        B.Table([0, 1], [0, 1], interpolation="cubic")


class Static(pdbfs.Rig):
    """A ramp from -2 to 2 and a sine through every static block."""

    def declare(self):
        self.ramp = B.Ramp(height=4.0, offset=-2.0, duration=1.0)
        self.sine = B.Sine(amplitude=1.5, f=2.0, phase=0.3)
        self.gain = B.Gain(k=-3.0)
        self.add = B.Add(k1=2.0, k2=-1.0)
        self.add3 = B.Add(n=3, k3=0.5)
        self.product = B.Product()
        self.limiter = B.Limiter(uMax=1.0, uMin=-0.5)
        self.dead = B.DeadZone(uMax=1.0, uMin=-0.5)
        self.integral = B.Integrator()
        r, s = self.ramp.y, self.sine.y
        self.connect(r, self.gain.u, self.add.u1, self.add3.u1, self.product.u1, self.limiter.u,
                     self.dead.u, self.integral.u)
        self.connect(s, self.add.u2, self.add3.u2, self.add3.u3, self.product.u2)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_static_blocks_pointwise(backend):
    res = Static().simulate(1.0, n_out=1001, backend=backend, **TIGHT)
    t = res.t
    r = -2.0 + 4.0 * t
    s = 1.5 * np.sin(2 * math.pi * 2.0 * t + 0.3)
    close = dict(rtol=0, atol=1e-14)
    assert np.allclose(res["ramp.y"], r, **close) and np.allclose(res["sine.y"], s, **close)
    assert np.allclose(res["gain.y"], -3.0 * r, **close)
    assert np.allclose(res["add.y"], 2.0 * r - s, **close)
    assert np.allclose(res["add3.y"], r + s + 0.5 * s, **close)
    assert np.allclose(res["product.y"], r * s, **close)
    assert np.allclose(res["limiter.y"], np.clip(r, -0.5, 1.0), **close)
    assert np.allclose(res["dead.y"], np.where(r > 1.0, r - 1.0, np.where(r < -0.5, r + 0.5, 0.0)),
                       **close)
    assert np.sum(r > 1.0) > 100 and np.sum(r < -0.5) > 100 and np.sum(np.abs(r) < 0.4) > 100


def test_limits_the_wrong_way_round_are_refused_naming_them():
    with pytest.raises(pdbfs.ParameterError, match=r"limiter \(Limiter\): the upper bound is "
                       r"below the lower bound \(limiter.uMin = 2, limiter.uMax = 1\)"):
        Static().simulate(0.1, params={"limiter.uMin": 2.0})
