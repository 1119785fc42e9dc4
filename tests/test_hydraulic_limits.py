"""A swept chamber that its piston empties: the run stops there with a
SolverError naming the chamber's volume, its bound and the time, on both
back ends with every method, in sweeps (the point failed, with the reason)
and in a summary that follows the pulse past t_end; never a negative volume
with the numbers after it (the hydraulic tutorial's buffer with a 50 mm2
orifice gave cylinder.chamber.Vc = -5e-5 m3 and exit status 0)."""
import re

import numpy as np
import pytest

import pdbfs
from pdbfs.components import Mass
from pdbfs.components.hydraulic import Cylinder, Orifice, Tank, Volume
from pdbfs.errors import ModelError, SolverError
from pdbfs.modelling import State, Variable

V, A = 2e-4, 2e-3          # the chamber: 0.1 m of oil under the piston
WIDE = {"orifice.A": 5e-5}  # the oil escapes too fast: the body reaches the chamber's bottom


class Buffer(pdbfs.Rig):
    """The hydraulic tutorial's buffer: a falling body stopped by a cylinder
    whose oil escapes through an orifice."""

    name = "hydraulic_buffer"
    summary_signals = {"pressure": "cylinder.chamber.p"}

    def declare(self):
        self.body = Mass(m=200.0, v0=2.0)
        self.cylinder = Cylinder(A=A, V=V, K=1.5e9)
        self.orifice = Orifice(A=1e-5)
        self.tank = Tank()
        self.connect(self.body.flange_b, self.cylinder.flange)
        self.connect(self.cylinder.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.tank.port)


@pytest.fixture(scope="module")
def rig():
    return Buffer()


def _refused(call) -> tuple[float, str]:
    with pytest.raises(SolverError) as err:
        call()
    msg = str(err.value)
    assert "\n" not in msg
    assert "cylinder.chamber.Vc (Chamber volume now)" in msg and "minimum 0 m3" in msg, msg
    assert "end stop" in msg, msg
    return float(re.search(r"at t = (\S+) s", msg).group(1)), msg


def test_the_chamber_is_declared_valid_above_zero_volume(rig):
    dae = rig.compile()
    assert [(v.name, kind, b) for v, kind, b in dae.limits] == [("cylinder.chamber.Vc", "min", 0.0)]
    assert not Volume().compile().limits           # a fixed chamber's volume cannot change


def test_a_bad_range_is_refused_where_it_is_declared():
    with pytest.raises(ModelError, match="min = 1.0 must be below max = 0.0"):
        Variable("m", "a length", min=1.0, max=0.0)
    with pytest.raises(ModelError, match="must be a finite number"):
        State("m", "a length", min="0")
    with pytest.raises(ModelError, match="must be a finite number"):
        State("m", "a length", max=float("nan"))


def test_every_back_end_and_method_stops_where_the_chamber_is_empty(rig):
    times = {}
    for backend, method in [("c", "erk"), ("c", "adams"), ("c", "bdf"), ("casadi", "adams"),
                            ("casadi", "bdf")]:
        times[backend, method], _ = _refused(
            lambda: rig.simulate(0.2, params=WIDE, backend=backend, method=method))
    t = np.array(list(times.values()))
    assert np.ptp(t) < 1e-5 * t.mean(), times
    # the time named is where the chamber's volume is gone: just before it, the body
    # has travelled the chamber's length V/A and the volume left is a sliver of V,
    # the geometric V - A s (the swept volume, a closed form)
    before = rig.simulate(float(t.min()) * (1 - 1e-4), params=WIDE, backend="casadi",
                          method="bdf")
    Vc, s = before["cylinder.chamber.Vc"], before["body.s"]
    assert Vc.min() > 0 and Vc[-1] < 1e-3 * V
    assert np.max(np.abs(Vc - (V - A * s))) < 1e-9 * V
    assert s[-1] == pytest.approx(V / A, rel=1e-3)


def test_a_run_that_keeps_its_oil_is_unchanged(rig):
    res = rig.simulate(0.2)
    assert res["cylinder.chamber.Vc"].min() > 0.9 * V - A * 0.01
    assert res.summary()["complete"]
    c = rig.simulate(0.2, backend="casadi", rtol=1e-10, atol=1e-14)
    assert res.summary()["peak_pressure"] == pytest.approx(c.summary()["peak_pressure"], rel=1e-6)


def test_a_summary_that_follows_the_pulse_into_the_bottom_says_so(rig):
    for backend in ("c", "casadi"):
        res = rig.simulate(0.1, params=WIDE, backend=backend)   # inside the run: all valid
        assert res["cylinder.chamber.Vc"].min() > 0
        t, msg = _refused(res.summary)
        assert t > 0.1 and "past t_end = 0.1 s" in msg


@pytest.mark.parametrize("options", [{}, {"backend": "casadi"}, {"trajectories": True}])
def test_a_sweep_marks_the_emptied_point_failed_with_the_reason(rig, options):
    res = pdbfs.sweep(rig, {"orifice.A": [1e-5, 5e-5, 2e-5]}, t_end=0.2, **options)
    assert [p.index for p in res.failed] == [1]
    reason = res.failed[0].error
    assert "cylinder.chamber.Vc" in reason and "minimum 0 m3" in reason, reason
    peaks = res.values("peak_pressure")
    assert np.isnan(peaks[1]) and np.all(np.isfinite(peaks[[0, 2]]))
    alone = rig.simulate(0.2, params={"orifice.A": 2e-5}).summary()["peak_pressure"]
    assert peaks[2] == pytest.approx(alone, rel=1e-6)
