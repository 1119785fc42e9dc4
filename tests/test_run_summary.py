"""The summary of a compiled run from the run itself (native/c/library/pdbfs_run_summary.c,
pdbfs/simulation/c_summary.py): the same figures as summary.py on the same
solution, nothing integrated again, summary.py asked where the run cannot
say (a pulse cut off at the horizon)."""
import warnings

import pytest

from pdbfs.errors import PulseIncompleteWarning
from pdbfs.models import paper_rig
from pdbfs.simulation.results import result as result_module
from pdbfs.simulation import summarize


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.mark.parametrize("method", ["erk", "adams"])
@pytest.mark.parametrize("params", [{}, {"hammer.v0": 5.5, "oil.k": 5e8}, {"hammer.v0": 1.5}])
def test_the_runs_summary_is_summary_py_on_the_same_run(rig, method, params, monkeypatch):
    res = rig.simulate(backend="c", method=method, params=params)
    assert res._fast is not None
    slow = summarize(res)                     # summary.py on this Result's own solution
    monkeypatch.setattr(result_module, "summarize", lambda r: pytest.fail("integrated again"))
    fast = res.summary()
    assert list(fast) == list(slow)
    for k, v in slow.items():
        if k in ("time_of_peak", "pulse_duration"):
            assert fast[k] == pytest.approx(v, abs=2e-9), k
        elif k == "restitution_coefficient":   # impulses integrated exactly here, on the grid there
            assert fast[k] == pytest.approx(v, rel=1e-6), k
        elif isinstance(v, float):
            assert fast[k] == pytest.approx(v, rel=3e-7), k
        else:
            assert fast[k] == v, k


def test_a_pulse_cut_off_goes_to_summary_py_with_its_warning(rig):
    res = rig.simulate(0.005, n_out=501)
    with pytest.warns(PulseIncompleteWarning, match="still running"):
        s = res.summary()
    assert s["complete"] is False and s["pulse_duration"] is None


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_a_peak_at_a_windows_end_is_read_on_the_windows_last_interval(rig, backend, monkeypatch):
    # a pulse still rising at t_end: its highest value so far is the last
    # sample, found on the interpolant of the last interval (trusted), not by
    # integrating again from the sample before some 25 times per peak
    from pdbfs.simulation.run.simulator import Simulator
    res = rig.simulate(0.002, n_out=201, backend=backend)      # 10 us apart: trusted
    p = res["oil.pressure"]
    steps = []
    monkeypatch.setattr(Simulator, "step", lambda *a, **k: steps.append(1) or pytest.fail("step"))
    assert res.peak("oil.pressure") == (res.t[-1], p[-1])
    assert res.peak("oil.pressure", window=(0.0, res.t[100])) == (res.t[100], p[100])
    assert res.peak("oil.pressure", sign=-1.0, window=(res.t[100], res.t[-1])) == (res.t[100],
                                                                                    p[100])
    with pytest.warns(PulseIncompleteWarning):
        assert res.summary()["complete"] is False
    assert not steps
    # the solution agrees: just inside the last interval it is lower
    monkeypatch.undo()
    assert res.value_at("oil.pressure", res.t[-1] - 1e-6) < p[-1]


def test_the_casadi_backend_keeps_summary_py(rig):
    res = rig.simulate(backend="casadi")
    assert res._fast is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert res.summary()["complete"] is True


def test_summary_run_does_not_import_result():
    import inspect
    from pdbfs.simulation.results import summary_run
    assert "from .result" not in inspect.getsource(summary_run)
