"""The absolute tolerance follows the relative one: a run converges as rtol
is tightened however small its signals. A 1 g hammer moves the piston by
4e-9 m; with atol fixed at 1e-10 its peak pressure stayed 7.5e-5 off
whatever the rtol (CVODE BDF at rtol 1e-14). Now atol, when not given, is
1e-10 down to the default rtol 1e-8 (the default run is unchanged) and
1e-2 * rtol below it; it can be given (``atol=``, ``--atol``). Every back end
and method honours it (the compiled explicit method, CVODE Adams and BDF,
CVODES through CasADi, IDAS), and sweeps, against a tight event-located
reference written from PHYSICS.md (paper_equations.py)."""
import json
import subprocess
import sys

import numpy as np
import pytest

import pdbfs
from paper_equations import blow_reference
from pdbfs import Parameter, eq
from pdbfs.components import Fixed, Mass
from pdbfs.components.translational.interfaces import PartialCompliant
from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig

TINY = {"hammer.m": 0.001}          # the piston moves 4e-9 m, the peak is 211 Pa


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.fixture(scope="module")
def peak():
    return blow_reference(rtol=1e-13, m1=0.001)["peak_pressure"]


@pytest.mark.parametrize("backend,method", [("c", "erk"), ("c", "adams"), ("c", "bdf"),
                                            ("casadi", "adams"), ("casadi", "bdf")])
def test_tightening_rtol_converges_on_a_tiny_signal(rig, peak, backend, method):
    err = {}
    for rtol in (1e-10, 1e-14):
        res = rig.simulate(params=TINY, rtol=rtol, backend=backend, method=method)
        assert res.settings["atol"] == pytest.approx(1e-2 * rtol)
        err[rtol] = abs(res.summary()["peak_pressure"] / peak - 1)
    assert err[1e-14] < 2e-9, err
    assert err[1e-14] < err[1e-10] or err[1e-10] < 2e-9, err


def test_the_default_run_keeps_its_tolerances(rig):
    for backend, rtol in (("c", 5e-8), ("casadi", 1e-8)):         # erk's default, CVODE's
        assert rig.simulate(backend=backend).settings["atol"] == 1e-10
        assert rig.simulate(backend=backend, rtol=rtol).settings["atol"] == 1e-10
    assert rig.simulate(rtol=1e-6).settings["atol"] == 1e-10       # looser: not looser atol
    given = rig.simulate(rtol=1e-12, atol=3e-11)
    assert given.settings["atol"] == 3e-11                          # as given


def test_an_atol_given_is_used(rig, peak):
    """A loose atol given with a tight rtol: the small signal is not resolved
    (the old behaviour, now asked for); tight, it is."""
    loose = rig.simulate(params=TINY, rtol=1e-14, atol=1e-10, backend="c", method="bdf")
    tight = rig.simulate(params=TINY, rtol=1e-14, atol=1e-18, backend="c", method="bdf")
    assert abs(loose.summary()["peak_pressure"] / peak - 1) > 1e-5
    assert abs(tight.summary()["peak_pressure"] / peak - 1) < 2e-9


class HardeningSpring(PartialCompliant):
    """f = k*(e + b*e^3), as in test_core."""

    k = Parameter(1.0, "N/m", "Linear stiffness", positive=True)
    b = Parameter(0.0, "1/m2", "Cubic hardening", min=0.0)

    def equations(self):
        return super().equations() + [eq(self.f, self.k * (self.s_rel + self.b * self.s_rel ** 3))]


class Chain(pdbfs.Rig):
    """frame - n springs in series (k each n times stiffer) - a body moving 6e-10 m."""

    def __init__(self, n, **kw):
        self._n = n
        super().__init__(**kw)

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=1.0, v0=2e-8)
        prev = self.frame.flange
        for i in range(self._n):
            spring = HardeningSpring(k=1000.0 * self._n, b=50.0 * self._n ** 2)
            setattr(self, f"k{i}", spring)
            self.connect(prev, spring.flange_a)
            prev = spring.flange_b
        self.connect(prev, self.body.flange_a)


def test_idas_honours_it():
    """Two springs in series keep their node as an algebraic variable (IDAS);
    one spring of the same stiffness is an ODE: the same motion. With atol
    1e-10 IDAS stayed 5e-4 off whatever the rtol."""
    two, one = Chain(2), Chain(1)
    assert not two.compile().is_ode and one.compile().is_ode
    ref = one.simulate(0.05, n_out=101, rtol=1e-14, atol=1e-30, backend="c", method="erk")
    scale = np.max(np.abs(ref["body.s"]))
    got = two.simulate(0.05, n_out=101, rtol=1e-14)
    assert got.settings["backend"] == "casadi" and got.settings["atol"] == pytest.approx(1e-16)
    assert np.max(np.abs(got["body.s"] - ref["body.s"])) < 1e-7 * scale


def test_sweeps_honour_it(rig, peak):
    """The compiled summary driver (a sweep's points) and the run, at rtol 1e-14."""
    from pdbfs.studies.sweeps.sweep import sweep
    for method in ("erk", "bdf"):
        s = sweep(rig, {"hammer.m": [0.001]}, rtol=1e-14, method=method, backend="c",
                  workers=1, progress=False)
        assert abs(s.values("peak_pressure")[0] / peak - 1) < 2e-9, method


@pytest.mark.parametrize("bad", [-1e-10, 0.0, float("nan"), float("inf"), [1e-10] * 6, "1e-10",
                                 True])
def test_a_bad_atol_is_refused_in_one_line(rig, bad):
    with pytest.raises(ParameterError, match=r"^atol = ") as err:
        rig.simulate(atol=bad)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize("bad", ["-1", "nan", "0"])
def test_the_command_refuses_a_bad_atol_before_any_work(tmp_path, bad):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--atol", bad,
                        "--out", str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=300, cwd=tmp_path)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and "atol" in lines[0], r.stderr
    assert not (tmp_path / "o").exists()


def test_the_command_takes_atol(tmp_path, peak):
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--set", "hammer.m=0.001",
                        "--method", "bdf", "--rtol", "1e-14", "--json", "--out",
                        str(tmp_path / "o")], capture_output=True, text=True, timeout=300,
                       cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert abs(json.loads(r.stdout)["peak_pressure"] / peak - 1) < 2e-9
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--set", "hammer.m=0.001",
                        "--method", "bdf", "--rtol", "1e-14", "--atol", "1e-10", "--json",
                        "--out", str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=300, cwd=tmp_path)
    assert r.returncode == 0 and abs(json.loads(r.stdout)["peak_pressure"] / peak - 1) > 1e-5
