"""Arguments that name variables or parameters: one name given as a str is
that name (never read letter by letter), a parameter named twice as an input
is refused in one line (no CasADi message, no input silently dropped), and
a boolean is no time."""
import numpy as np
import pytest

from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig
from pdbfs.simulation import trajectory_function

RIG = paper_rig()


def test_linearize_refuses_an_input_named_twice():
    with pytest.raises(ParameterError) as err:
        RIG.linearize(0.004, inputs=["oil.k", "oil.k"])
    msg = str(err.value)
    assert "'oil.k'" in msg and "twice" in msg and "\n" not in msg, msg


@pytest.mark.parametrize("at", [True, False, np.bool_(True)])
def test_linearize_refuses_a_boolean_for_the_time(at):
    with pytest.raises(ParameterError, match="at="):
        RIG.linearize(at)


def test_linearize_takes_one_name_as_a_str():
    one = RIG.linearize(0.004, inputs="oil.k", outputs="oil.pressure")
    listed = RIG.linearize(0.004, inputs=["oil.k"], outputs=["oil.pressure"])
    assert one.inputs == ["oil.k"] and one.outputs == ["oil.pressure"]
    assert one.B.shape == (listed.A.shape[0], 1) and one.C.shape == (1, listed.A.shape[0])
    for m in "ABCD":
        np.testing.assert_array_equal(getattr(one, m), getattr(listed, m))
    # the pressure is k x / A: its derivative in x and in k is not zero
    assert np.any(one.C != 0) and np.any(one.D != 0)


def test_linearize_refuses_an_output_twice():
    """Two rows of one output are no two outputs (as two columns of one input)."""
    with pytest.raises(ParameterError, match="outputs: 'oil.pressure' is listed twice"):
        RIG.linearize(0.004, outputs=["oil.pressure", "oil.pressure"])


@pytest.mark.parametrize("bad", [3, ["oil.k", 3], {"oil.k": 1}])
def test_linearize_refuses_what_is_no_name(bad):
    with pytest.raises(ParameterError, match="inputs"):
        RIG.linearize(inputs=bad)


def test_trajectory_function_takes_one_input_as_a_str_and_refuses_one_twice():
    f = trajectory_function(RIG, "oil.pressure", t_end=0.004, n_out=5, inputs="oil.k")
    g = trajectory_function(RIG, ["oil.pressure"], t_end=0.004, n_out=5, inputs=["oil.k"])
    k = 2.228e8
    np.testing.assert_allclose(np.array(f(k)), np.array(g(k)), rtol=0, atol=0)
    # the same input twice left its first column without effect (a zero derivative)
    with pytest.raises(ParameterError, match="'oil.k' is listed twice"):
        trajectory_function(RIG, "oil.pressure", t_end=0.004, n_out=5, inputs=["oil.k", "oil.k"])


def test_result_exports_take_one_name_as_a_str(tmp_path):
    res = RIG.simulate(0.002, n_out=5)
    assert list(res.as_dict("oil.pressure")) == ["time", "oil.pressure"]
    res.to_csv(tmp_path / "p.csv", names="oil.pressure")
    header = (tmp_path / "p.csv").read_text().splitlines()[0]
    assert header == "time [s],oil.pressure [Pa]"
    assert list(res.to_pandas("oil.pressure").columns) == ["oil.pressure"]


def test_calibration_bounds_take_one_bound_as_a_str():
    from pdbfs.studies.fitting.arguments import check_fit_arguments
    from pdbfs.studies.fitting.free_parameters import parse_bounds
    assert parse_bounds("oil.k=1e8:1e9") == {"oil.k": (1e8, 1e9)}
    check_fit_arguments(free="oil.k", bounds="oil.k=1e8:1e9", start=None, params=None,
                        starts=1, t_end=None)


@pytest.mark.filterwarnings("ignore::pdbfs.errors.SampleTooSmallWarning")
def test_sensitivity_checks_its_outputs_before_the_sweep(monkeypatch):
    import sys
    import pdbfs.studies  # noqa: F401  (the package's name sensitivity is the function)
    S = sys.modules["pdbfs.studies.sensitivity"]

    def no_sweep(*a, **k):
        raise AssertionError("the sweep ran before the outputs were checked")
    monkeypatch.setattr(S, "sweep", no_sweep)
    with pytest.raises(ParameterError, match="no summary value 'peak'"):
        S.sensitivity(RIG, {"hammer.v0": (2.0, 3.0)}, n=64, outputs=["peak", "time_of_peak"])
    with pytest.raises(ParameterError, match="outputs = 3"):
        S.sensitivity(RIG, {"hammer.v0": (2.0, 3.0)}, n=64, outputs=3)
    monkeypatch.undo()
    # one key as a str: that key, not its letters
    s = S.sensitivity(RIG, {"hammer.v0": (2.0, 3.0), "oil.k": (1e8, 3e8)}, n=64,
                      outputs="peak_pressure", workers=1, progress=False)
    assert s.outputs == ["peak_pressure"] and set(s.S1) == {"peak_pressure"}
