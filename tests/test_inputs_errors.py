"""Bad inputs are refused in one line naming the input and what is wrong,
before anything is integrated: in simulate, in the command line (exit
status 2, nothing written), in linearize and in the FMU export."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.models import RIGS

from input_rigs import BaseExcited, CommandedPulse, Pushed

T_END = 0.5
GOOD = (np.array([0.0, 0.2, 0.5]), np.array([0.0, 1.0, 1.0]))


@pytest.mark.parametrize("inputs, culprit", [
    ({"v": 1.0}, "inputs: 'v' is not an input of rig Pushed (its inputs: u)"),
    ({"uu": 1.0}, "did you mean u?"),
    ([("u", 1.0)], "give a dict of input name -> trace"),
    ({"u": "high"}, "inputs: u = 'high': give a trace (t, u) of times and values"),
    ({"u": ([0.0, 0.5], [1.0, 2.0, 3.0])}, "inputs: u: 2 times but 3 values"),
    ({"u": ([0.0, 0.3, 0.2, 0.5], [0.0, 1.0, 1.0, 1.0])},
     "inputs: u: the times must not decrease: 0.2 s (sample 3) after 0.3 s"),
    ({"u": ([0.0, 0.2, 0.2, 0.2, 0.5], [0.0, 0.0, 1.0, 2.0, 2.0])},
     "inputs: u: three samples at t = 0.2 s; a jump is two samples at one time"),
    ({"u": ([0.0, 0.2, 0.5], [0.0, math.nan, 1.0])}, "inputs: u: value 2 is nan at t = 0.2 s"),
    ({"u": ([0.0, math.inf, 0.5], [0.0, 1.0, 1.0])}, "inputs: u: time 2 is inf"),
    ({"u": ([0.0, 0.4], [0.0, 1.0])}, "inputs: u: the trace covers 0 .. 0.4 s, the run 0 .. 0.5 s"),
    ({"u": ([0.1, 0.5], [0.0, 1.0])}, "inputs: u: the trace covers 0.1 .. 0.5 s"),
    ({"u": ([0.0], [1.0])}, "inputs: u: a trace needs two samples at least"),
    ({"u": math.nan}, "inputs: u = nan: must be finite"),
    ({"u": True}, "inputs: u = True: give a trace"),
    ({"u": np.zeros((3, 3))}, "inputs: u = an array of shape (3, 3): give a trace"),
    ({"u": (np.zeros((2, 2)), np.zeros((2, 2)))}, "the trace (t, u) takes two lists of numbers"),
    ({"u": lambda t: 1.0 / 0.0}, "inputs: u(t) raised ZeroDivisionError at t = 0 s: float "
                                 "division by zero; sampled over the run, 0 .. 0.5 s"),
    ({"u": lambda t: math.nan}, "inputs: u(t) = nan at t = 0 s: must be finite; sampled over"),
    # the time it fails at, said as a time of f (not to be read as the run's length)
    ({"u": lambda t: 0.0 if t == 0 else 1.0 / 0.0}, "inputs: u(t) raised ZeroDivisionError at "
                                                   "t = 0.000488281 s"),
])
def test_bad_inputs_are_refused_in_one_line(inputs, culprit):
    with pytest.raises(pdbfs.ParameterError) as err:
        Pushed().simulate(T_END, n_out=11, inputs=inputs)
    assert culprit in str(err.value) and "\n" not in str(err.value)


def test_a_rig_without_inputs_says_so():
    with pytest.raises(pdbfs.ParameterError, match="rig pdbfs_paper has no inputs"):
        pdbfs.simulate(RIGS["paper"](), 0.01, inputs={"command": 1.0})


def test_the_settings_are_checked_before_the_inputs_and_both_before_any_work():
    with pytest.raises(pdbfs.ParameterError, match="rtol"):
        Pushed().simulate(T_END, inputs={"u": ([0.0, 0.1], [0.0, 1.0])}, rtol=-1.0)
    rig = Pushed()
    with pytest.raises(pdbfs.ParameterError, match="covers"):
        rig.simulate(T_END, inputs={"u": ([0.0, 0.1], [0.0, 1.0])}, backend="casadi")
    assert pdbfs.simulation.Simulator.of(rig)._last_stats == {}     # nothing integrated


def test_an_fmu_of_a_rig_that_differentiates_an_input_is_refused_in_one_line(tmp_path):
    """A rig with inputs exports them as FMU inputs (tests/test_fmu_inputs.py);
    one whose equations use an input's rate cannot, since an importer gives values."""
    with pytest.raises(pdbfs.ExportError) as err:
        BaseExcited().export_fmu(tmp_path / "base.fmu")
    assert "input base is differentiated" in str(err.value) and "\n" not in str(err.value)
    assert not list(tmp_path.iterdir())


def test_linearize_refuses_unknown_and_differentiated_inputs():
    with pytest.raises(pdbfs.ParameterError, match="input 'v' is not a parameter of rig Pushed nor one of its inputs"):
        Pushed().linearize(inputs=["v"])
    with pytest.raises(pdbfs.ParameterError) as err:
        BaseExcited().linearize(inputs=["base"], outputs=["body.s"])
    assert "input base is differentiated by rig BaseExcited" in str(err.value)
    assert "\n" not in str(err.value)


@pytest.fixture
def commanded(monkeypatch):
    """The commanded pulse rig reachable by name from the command line."""
    monkeypatch.setitem(RIGS, "commanded", CommandedPulse)
    return "commanded"


@pytest.mark.parametrize("arg, culprit", [
    ("nope=1", "--input 'nope=1': 'nope' is not an input of rig commanded_pulse (its inputs: "
     "command)"),
    ("command", "--input 'command': expected NAME=FILE.csv or NAME=VALUE"),
    ("command=missing.csv", "--input command: file 'missing.csv': no such file"),
    ("command=bad.csv", "column command, data row 2: x is not a number"),
    ("command=short.csv", "inputs: command: the trace covers 0 .. 0.01 s, the run 0 .. 0.02 s"),
    ("command=kpa.csv", "column 'command [kPa]' is in kPa, but input command is in 1"),
])
def test_the_command_line_refuses_bad_input_files(commanded, tmp_path, monkeypatch, capsys, arg,
                                                  culprit):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "bad.csv").write_text("time [s],command [1]\n0,0\n0.01,x\n0.02,0\n")
    (tmp_path / "short.csv").write_text("0,0\n0.01,1\n")
    (tmp_path / "kpa.csv").write_text("time [s],command [kPa]\n0,0\n0.02,1\n")
    code = main(["simulate", "--rig", commanded, "--input", arg, "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and culprit in err and err.count("\n") == 1, err
    assert not (tmp_path / "out").exists()


def test_a_function_that_fails_on_arrays_warns_nothing(recwarn):
    """numpy's divide-by-zero warning on f's array call is no second message:
    the refusal names the time."""
    with pytest.raises(pdbfs.ParameterError, match=r"u\(t\) = inf at t = 0 s: must be finite"):
        Pushed().simulate(T_END, n_out=11, inputs={"u": lambda t: 1.0 / np.asarray(t)})
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]
