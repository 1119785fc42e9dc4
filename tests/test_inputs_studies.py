"""The rig's inputs in sweeps and calibration: the same command at every
point, a list of commands as a sweep dimension (its column the command's
number), constant commands on the compiled summary driver, the points'
trajectories; a calibration recovers the chamber's bulk modulus and the
drain's area from a pressure trace simulated with a known command, given
as the rig's input."""
import numpy as np
import pytest

import pdbfs

from input_rigs import COMMAND, CommandedPulse, ScaledCommandPulse

T_END = 0.02
KEYS = ("peak_pressure", "time_of_peak", "pulse_duration")
t_cmd, u_cmd = COMMAND
COMMANDS = [(t_cmd, s * u_cmd) for s in (0.5, 0.75, 1.0)]


def direct(command, backend, **params):
    return CommandedPulse().simulate(T_END, inputs={"command": command}, params=params,
                                     backend=backend).summary()


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_a_sweep_over_parameters_and_a_list_of_commands(backend):
    rig = CommandedPulse()
    res = pdbfs.sweep(rig, {"valve.A": [6e-5, 8e-5], "command": COMMANDS}, backend=backend,
                      t_end=T_END, workers=1)
    frame = res.frame
    assert frame["command"].tolist() == [0, 1, 2, 0, 1, 2] and not any(frame["error"])
    for _, row in frame.iterrows():
        want = direct(COMMANDS[int(row["command"])], backend, **{"valve.A": row["valve.A"]})
        for key in KEYS:
            assert row[key] == pytest.approx(want[key], rel=1e-12), key
    # a bigger command, a higher peak (the valve opens further)
    assert np.all(np.diff(frame["peak_pressure"].to_numpy()[:3]) > 0)


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_the_same_command_at_every_point(backend):
    res = pdbfs.sweep(CommandedPulse(), {"drain.A": [3e-5, 4e-5]}, inputs={"command": COMMANDS[1]},
                      backend=backend, t_end=T_END, workers=1)
    for _, row in res.frame.iterrows():
        want = direct(COMMANDS[1], backend, **{"drain.A": row["drain.A"]})
        assert row["peak_pressure"] == pytest.approx(want["peak_pressure"], rel=1e-12)


def test_an_input_that_scales_the_command_is_a_sweep_dimension_on_the_summary_driver():
    """An input that is a parameter of the command (its scale): numbers are
    entries of each point's parameter vector, the compiled summary driver
    runs them (the column holds the numbers), with the figures of single
    runs (measured: peak within 1e-11, the time of the peak within 2e-8)."""
    from pdbfs.studies.sweeps.inputs import split_inputs
    from pdbfs.studies.sweeps.runner import Runner, Settings
    rig = ScaledCommandPulse()
    sim = pdbfs.simulation.Simulator.of(rig)
    values, ins = split_inputs(sim, {"scale": [0.5, 0.75, 1.0]}, None, T_END, 2001)
    assert ins.constant and values == {"scale": [0.5, 0.75, 1.0]}
    assert Runner(sim, list(values), {}, Settings(t_end=T_END, backend="c", method="erk"),
                  ins).fast is not None
    res = pdbfs.sweep(rig, {"scale": [0.5, 0.75, 1.0]}, backend="c", t_end=T_END, workers=1)
    assert res.frame["scale"].tolist() == [0.5, 0.75, 1.0]
    for k, scale in enumerate((0.5, 0.75, 1.0)):
        want = rig.simulate(T_END, inputs={"scale": scale}, backend="c").summary()
        same = CommandedPulse().simulate(T_END, inputs={"command": (t_cmd, scale * u_cmd)},
                                         backend="c", rtol=1e-10).summary()
        assert res.frame["peak_pressure"][k] == pytest.approx(want["peak_pressure"], rel=1e-9)
        assert res.frame["pulse_duration"][k] == pytest.approx(want["pulse_duration"], rel=1e-9)
        assert res.frame["time_of_peak"][k] == pytest.approx(want["time_of_peak"], rel=1e-6)
        assert want["peak_pressure"] == pytest.approx(same["peak_pressure"], rel=1e-7)


def test_trajectories_from_worker_processes_read_their_inputs():
    res = pdbfs.sweep(CommandedPulse(), {"command": COMMANDS}, t_end=T_END, trajectories=True,
                      workers=2, backend="casadi")
    for k, command in enumerate(COMMANDS):
        got = res[k].result
        want = CommandedPulse().simulate(T_END, inputs={"command": command}, backend="casadi")
        assert np.allclose(got["command.y"], np.interp(got.t, *command), rtol=0, atol=1e-15)
        assert got.value_at("chamber.p", 0.005173) == pytest.approx(
            want.value_at("chamber.p", 0.005173), rel=1e-12)          # between output points


def test_a_single_trace_where_a_list_belongs_is_refused():
    with pytest.raises(pdbfs.ParameterError, match="input command takes a list of traces"):
        pdbfs.sweep(CommandedPulse(), {"command": COMMANDS[0]}, t_end=T_END)
    with pytest.raises(pdbfs.ParameterError, match="inputs: command: the trace covers"):
        pdbfs.sweep(CommandedPulse(), {"command": [(t_cmd[:2], u_cmd[:2])]}, t_end=T_END)


def test_calibration_with_the_measured_command_as_an_input():
    """A 'measurement' made by the rig itself (K = 1.5 GPa, drain area 40 mm^2)
    with a known command; from 1 GPa and 30 mm^2 the fit finds both back to
    1e-8 at rtol 1e-10 (measured 6e-10 and 1.3e-9; 1.5e-7 at the default
    rtol 1e-8, as the same rig with the command as a Table block), with the
    command given as the rig's input."""
    rig = CommandedPulse()
    t = np.linspace(0.0, T_END, 401)
    measured = rig.simulate(T_END, t_out=t, inputs={"command": COMMAND}, rtol=1e-10, atol=1e-6)
    cal = pdbfs.calibrate(rig, (t, measured["chamber.p"]), free=["chamber.K", "drain.A"],
                          start={"chamber.K": 1.0e9, "drain.A": 3e-5}, starts=1, rtol=1e-10,
                          inputs={"command": COMMAND})
    assert cal.params["chamber.K"] == pytest.approx(1.5e9, rel=1e-8)
    assert cal.params["drain.A"] == pytest.approx(4e-5, rel=1e-8)
    assert not cal.undetermined
    # without the command the valve stays shut: no pulse to fit
    with pytest.raises(pdbfs.PdbfsError):
        pdbfs.calibrate(rig, (t, measured["chamber.p"]), free=["chamber.K"], starts=1)
    with pytest.raises(pdbfs.ParameterError, match="inputs and fit_offset together"):
        pdbfs.calibrate(rig, (t, measured["chamber.p"]), free=["chamber.K"], fit_offset=True,
                        inputs={"command": COMMAND})
    with pytest.raises(pdbfs.ParameterError, match="inputs: command: the trace covers"):
        pdbfs.calibrate(rig, (t, measured["chamber.p"]), free=["chamber.K"],
                        inputs={"command": (t_cmd[:3], u_cmd[:3])})
