"""Physically impossible results are not given without a word: an absolute
tolerance above the states' scale is refused before any work (atol 1e10
gave the paper rig a restitution of 1.25 and a 125 MPa peak), and a
restitution coefficient above 1 warns, naming the likely cause (contact.gap
= -1 m gave 801.7 and 110 GPa in silence)."""
import subprocess
import sys
import warnings

import pytest

from pdbfs.errors import ImplausibleResultWarning, ParameterError
from pdbfs.models import paper_rig
from pdbfs.simulation.results.summary import implausible


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_an_atol_above_the_states_scale_is_refused(rig, backend, monkeypatch):
    from pdbfs.simulation import Simulator
    sim = Simulator.of(rig)
    monkeypatch.setattr(sim, "integrate", lambda *a, **k: pytest.fail("integrated"))
    monkeypatch.setattr(sim, "integrate_c", lambda *a, **k: pytest.fail("integrated"))
    with pytest.raises(ParameterError, match=r"atol = 1e\+10 .*hammer\.v = 2\.73 m/s"):
        rig.simulate(atol=1e10, backend=backend)
    with pytest.raises(ParameterError, match="atol = 3 "):
        rig.simulate(atol=3.0, params={"hammer.v0": 2.9}, backend=backend)


def test_the_command_line_refuses_it_in_one_line(tmp_path):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--atol", "1e10", "--json"],
                       capture_output=True, text=True, cwd=tmp_path)
    assert r.returncode == 2 and not r.stdout and "Traceback" not in r.stderr
    assert r.stderr.strip().count("\n") == 0 and "--atol 1e+10" in r.stderr
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_a_restitution_above_one_names_the_interpenetration(rig, backend):
    res = rig.simulate(params={"contact.gap": -1.0}, backend=backend)
    with pytest.warns(ImplausibleResultWarning, match="above 1.*already .* N at t = 0.*gap"):
        e = res.summary()["restitution_coefficient"]
    assert e > 1
    with pytest.warns(ImplausibleResultWarning):      # given again with the kept summary
        res.summary()


def test_a_restitution_above_one_without_an_initial_force_names_the_tolerances(rig):
    res = rig.simulate(backend="casadi")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert res.summary()["restitution_coefficient"] < 1      # a sound blow: nothing
    got = implausible(res, {"restitution_coefficient": 1.25})
    assert len(got) == 1 and got[0].category is ImplausibleResultWarning
    assert "rtol = 1e-08, atol = 1e-10" in str(got[0].message)
    assert implausible(res, {"restitution_coefficient": 0.92}) == []
