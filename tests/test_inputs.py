"""A rig driven through its inputs (simulate(..., inputs=...)), against
closed forms, on both back ends: a mass-spring-damper pushed by an Input
through SignalForce follows its analytic step, ramp and sine responses;
the same rig with the signal given as an input and as a source block
inside it agrees to 1e-9; an input's breakpoints are time events (a kink
between output points lands exactly, whatever the grid); the summary and
values between output points use the inputs too."""
import numpy as np
import pytest

import pdbfs
from pdbfs.components import blocks as B

from input_rigs import (BACKENDS, COMMAND, TIGHT, BaseExcited, CommandedPulse, K, Pushed,
                        ShakenMass, msd_ramp, msd_sine, msd_step)

F, TS = 10.0, 0.1003          # N, s: the step (between output points of a 1 ms grid)


def step_trace(t_end=1.5):
    """A step of F at TS: one time twice (before and after the jump)."""
    return np.array([0.0, TS, TS, t_end]), np.array([0.0, 0.0, F, F])


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_step_trace_gives_the_step_response(backend):
    res = Pushed().simulate(1.5, n_out=1501, inputs={"u": step_trace()}, backend=backend, **TIGHT)
    # measured: 5e-12 m (c), 2e-11 m (casadi) of a 0.025 m static deflection
    assert np.max(np.abs(res["pos.y"] - msd_step(res.t, F, TS))) < 1e-8 * F / K
    assert np.array_equal(res["push.force"], np.where(res.t >= TS, F, 0.0))
    assert res.stats["segments"] == 2


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_ramp_starting_between_output_points_lands_exactly(backend):
    """The kink at tk lies between output points; on a grid of 3 points
    (none near it) the solution is the same: the breakpoint is a time event."""
    tk, rate = 0.0537, 3.0
    trace = ([0.0, tk, 1.0], [0.0, 0.0, rate * (1.0 - tk)])
    scale = rate / K
    for n_out in (101, 3):
        res = Pushed().simulate(1.0, n_out=n_out, inputs={"u": trace}, backend=backend, **TIGHT)
        # measured: 5e-13 m of 7e-3 m
        assert np.max(np.abs(res["body.s"] - msd_ramp(res.t, rate, tk))) < 1e-9 * scale
        assert res.value_at("body.s", 0.3217) == pytest.approx(
            msd_ramp(np.array([0.3217]), rate, tk)[0], rel=0, abs=1e-9 * scale)
        assert res.value_at("push.force", 0.3217) == pytest.approx(rate * (0.3217 - tk), rel=1e-12)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_finely_sampled_sine_converges_at_second_order(backend):
    """The sine as samples every h, interpolated linearly: the force is off
    by up to h^2 w^2 A / 8 between samples, the response by about 2e-5 of
    its size at h = 1 ms (w = 15.7 rad/s), 16 times less at h / 4."""
    A, f = 5.0, 2.5
    errors = []
    for n in (2001, 8001) if backend == "c" else (2001,):
        tt = np.linspace(0.0, 2.0, n)
        res = Pushed().simulate(2.0, n_out=2001, inputs={"u": (tt, A * np.sin(2 * np.pi * f * tt))},
                                backend=backend, **TIGHT)
        want = msd_sine(res.t, A, f)
        errors.append(np.max(np.abs(res["body.s"] - want)) / np.max(np.abs(want)))
    assert 1e-5 < errors[0] < 3e-5            # measured 2.06e-5 on both back ends
    if len(errors) > 1:
        assert errors[0] / errors[1] == pytest.approx(16.0, rel=0.05)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_function_of_time_is_followed_to_its_stated_accuracy(backend):
    A, f = 5.0, 2.5
    res = Pushed().simulate(2.0, n_out=2001, inputs={"u": lambda t: A * np.sin(2 * np.pi * f * t)},
                            backend=backend, **TIGHT)
    want = msd_sine(res.t, A, f)
    # sampled to 1e-6 of its amplitude at every interval's middle (input_function.py): measured
    # 3.8e-7 (c), 4.8e-7 (casadi) of the response
    assert np.max(np.abs(res["body.s"] - want)) < 1e-6 * np.max(np.abs(want))
    assert res.stats["segments"] > 5000
    # a scalar-only function (no arrays) is evaluated point by point; its jump is located
    # within 1e-9 of the run (a ramp 5e-10 s wide): measured 5.5e-10 m of 0.025 m (casadi)
    step = Pushed().simulate(0.5, n_out=501, inputs={"u": lambda t: F if t >= 0.25 else 0.0},
                             backend=backend, **TIGHT)
    assert np.max(np.abs(step["pos.y"] - msd_step(step.t, F, 0.25))) < 1e-7 * F / K


@pytest.mark.parametrize("backend", BACKENDS)
def test_an_input_and_a_source_block_agree(backend):
    """A Step and a linear Table inside the rig, and the same signals given
    as inputs: every variable agrees to 1e-9 of its size."""
    def agree(a, b):
        for name in ("body.s", "body.v", "body.a", "spring.f", "push.force"):
            scale = max(np.max(np.abs(a[name])), 1e-300)
            assert np.max(np.abs(a[name] - b[name])) < 1e-9 * scale, name
    block = Pushed(B.Step(unit="N", height=F, start_time=TS)).simulate(
        1.5, n_out=1501, backend=backend, **TIGHT)
    given = Pushed().simulate(1.5, n_out=1501, inputs={"u": step_trace()}, backend=backend, **TIGHT)
    agree(block, given)
    tt = np.linspace(0.0, 1.0, 41)
    uu = 5.0 * np.sin(2 * np.pi * 2.5 * tt) + 2.0 * tt
    block = Pushed(B.Table(tt, uu, unit="N")).simulate(1.0, n_out=1001, backend=backend, **TIGHT)
    given = Pushed().simulate(1.0, n_out=1001, inputs={"u": (tt, uu)}, backend=backend, **TIGHT)
    agree(block, given)


@pytest.mark.parametrize("backend", BACKENDS)
def test_an_input_differentiated_once_prescribes_a_moving_base(backend):
    """SignalPosition moved by an input: the damper needs its rate, the
    slope of each segment. A Ramp block inside the rig gives the same
    motion; at the ramp's two kinks (output points) the input's rate is the
    segment's after the kink, the block's the mean of both sides."""
    tight = dict(rtol=1e-12, atol=1e-14)   # CVODES's block run is 3e-10 m off at rtol 1e-10
    ramp = BaseExcited(B.Ramp(unit="m", height=0.01, duration=0.1, start_time=0.1)).simulate(
        1.0, n_out=1001, backend=backend, **tight)
    given = BaseExcited().simulate(1.0, n_out=1001, backend=backend, **tight,
                                   inputs={"base": ([0.0, 0.1, 0.2, 1.0], [0.0, 0.0, 0.01, 0.01])})
    kinks = np.isin(given.t, [0.1, 0.2])
    for name in ("body.s", "body.v", "damper.f"):
        scale = np.max(np.abs(ramp[name]))
        assert np.max(np.abs(ramp[name] - given[name])[~kinks]) < 1e-9 * scale, name
    at = given.t == 0.1                        # right-continuous: the base moves at 0.1 m/s
    assert given["damper.v_rel"][at][0] == pytest.approx(given["body.v"][at][0] - 0.1, rel=1e-12)


def test_an_input_differentiated_twice_is_refused_naming_it():
    with pytest.raises(pdbfs.ModelError) as err:
        ShakenMass().compile()
    assert str(err.value).startswith("input base: the rig needs its second derivative")
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("backend", BACKENDS)
def test_inputs_not_given_hold_their_start_and_numbers_are_held(backend):
    res = Pushed(B.Input("N", start=3.0)).simulate(1.0, n_out=501, backend=backend, **TIGHT)
    assert np.max(np.abs(res["pos.y"] - msd_step(res.t, 3.0, 0.0))) < 1e-8 * 3.0 / K
    res = Pushed(B.Input("N", start=3.0)).simulate(1.0, n_out=501, inputs={"u": 8.0},
                                                   backend=backend, **TIGHT)
    assert np.max(np.abs(res["pos.y"] - msd_step(res.t, 8.0, 0.0))) < 1e-8 * 8.0 / K
    assert Pushed().inputs()[0].name == "u" and "u" not in Pushed().compile().p_names


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_summary_and_values_off_the_grid_use_the_inputs(backend):
    """The pulse rig's valve commanded by an input and by a Table of the same
    command: the same summary (its own solution past the output grid, the
    peak located between output points) and the same values between points."""
    tight = dict(rtol=1e-10, atol=1e-4)
    table = CommandedPulse(B.Table(*COMMAND)).simulate(0.02, n_out=201, backend=backend, **tight)
    given = CommandedPulse().simulate(0.02, n_out=201, inputs={"command": COMMAND},
                                      backend=backend, **tight)
    a, b = table.summary(), given.summary()
    assert a["complete"] and b["complete"]
    for key in ("peak_pressure", "pulse_duration"):
        assert b[key] == pytest.approx(a[key], rel=1e-8), key
    # the time of a flat peak: measured 1.5e-8 apart (casadi)
    assert b["time_of_peak"] == pytest.approx(a["time_of_peak"], rel=1e-6)
    for t in (0.00123, 0.00471, 0.0111):
        assert given.value_at("chamber.p", t) == pytest.approx(table.value_at("chamber.p", t),
                                                               rel=1e-8)
        assert given.value_at("command.y", t) == pytest.approx(np.interp(t, *COMMAND), rel=1e-12)
    t_peak, peak = given.peak("chamber.p")
    assert peak == pytest.approx(table.peak("chamber.p")[1], rel=1e-8)
    assert t_peak == pytest.approx(table.peak("chamber.p")[0], rel=1e-6)


def test_the_summary_follows_a_pulse_past_t_end_only_as_far_as_the_inputs_go():
    """Cut at 8 ms the pulse is still running: with a command that goes on
    to 50 ms the summary finds its end past t_end; with one that ends at
    t_end it says the pulse has not ended, and guesses nothing."""
    rig = CommandedPulse()
    with pytest.warns(pdbfs.PulseIncompleteWarning, match="it ends at about 0.014"):
        longer = rig.simulate(0.008, inputs={"command": COMMAND}).summary()
    assert longer["complete"] is False and longer["pulse_duration"] is None
    cut = (np.append(COMMAND[0][:4], 0.008), np.append(COMMAND[1][:4], 0.0))
    with pytest.warns(pdbfs.PulseIncompleteWarning, match="has not ended by 0.008 s"):
        ended_here = rig.simulate(0.008, inputs={"command": cut}).summary()
    assert ended_here["complete"] is False
