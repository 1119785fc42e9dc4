"""trajectory_function checks the values it is called with as simulate
does (one per input, each in its parameter's range), and integrates a rig
with switch times piece by piece between them."""
import numpy as np
import pytest

from pdbfs import trajectory_function
from pdbfs.errors import ParameterError
from pdbfs.models import hydraulic_pulse_rig, paper_rig


@pytest.fixture(scope="module")
def f():
    return trajectory_function(paper_rig(), ["oil.pressure"], inputs=["oil.k", "seal.c"],
                               n_out=201)


def test_one_value_for_two_inputs_is_refused(f):
    with pytest.raises(ParameterError, match="1 value.*2 input"):
        f([2.2e8])
    with pytest.raises(ParameterError, match="3 value"):
        f([2.2e8, 2.5e4, 1.0])


@pytest.mark.parametrize("k", [0.0, -1.0, float("nan")])
def test_values_simulate_refuses_are_refused(f, k):
    with pytest.raises(ParameterError, match="oil.k"):
        f([k, 2.5e4])


def test_good_values_give_simulates_answer(f):
    y = np.asarray(f([2.0e8, 3.0e4])).ravel()
    ref = paper_rig().simulate(0.02, n_out=201, params={"oil.k": 2.0e8, "seal.c": 3.0e4})
    assert np.max(np.abs(y - ref["oil.pressure"])) < 1e-6 * np.max(ref["oil.pressure"])


def test_a_late_valve_is_not_stepped_over():
    params = {"valve.t_open": 0.008, "valve.t_close": 0.0125}
    g = trajectory_function(hydraulic_pulse_rig(), ["chamber.p"], inputs=["valve.A"],
                            params=params, n_out=5)
    ref = hydraulic_pulse_rig().simulate(0.02, n_out=5, params=params)
    y = np.asarray(g([8e-5])).ravel()
    assert y[-1] > 1e6
    assert y == pytest.approx(ref["chamber.p"], rel=1e-5)
    # a switch time as an input: integrated through in steps no longer than the grid's
    h = trajectory_function(hydraulic_pulse_rig(), ["chamber.p"], n_out=2001,
                            inputs=["valve.t_open", "valve.t_close"])
    full = hydraulic_pulse_rig().simulate(0.02, n_out=2001, params=params)
    assert np.asarray(h([0.008, 0.0125])).ravel() == pytest.approx(full["chamber.p"], rel=1e-4)
