"""FMUs of rigs whose start is solved: the FMU solves the same start in its
initialization mode (a generated damped Newton, pdbfs.native.initial), at
the parameters it is given; readable after ExitInitializationMode; a start
it cannot solve is an error of ExitInitializationMode, never a wrong start."""
import numpy as np
import pytest

fmpy = pytest.importorskip("fmpy")
from fmpy import simulate_fmu  # noqa: E402

from pdbfs.models import drop_rig, hydraulic_pulse_rig  # noqa: E402
from fmu_support import fmu_log_text


@pytest.fixture(scope="module")
def rest_fmu(tmp_path_factory):
    return str(drop_rig(rest=True).export_fmu(tmp_path_factory.mktemp("rest") / "rest.fmu"))


@pytest.fixture(scope="module")
def line_fmu(tmp_path_factory):
    return str(hydraulic_pulse_rig(line=True).export_fmu(
        tmp_path_factory.mktemp("line") / "line.fmu"))


# co-simulation's auto takes the explicit method here (0.01 s: 70 rad of the
# breech mode), which holds the rest to its absolute tolerance (rtol 1e-8 x
# the 1 mm nominal: 1e-11 m; measured 3.5e-12, as backend="c"'s 2e-12), where
# CVODE's BDF damps it to roundoff
@pytest.mark.parametrize("fmi_type, method, drift", [("ModelExchange", None, 1e-12), ("CoSimulation", 1, 1e-12),
                                                     ("CoSimulation", 0, 1e-11)])
def test_fmu_starts_at_rest_where_pdbfs_solves_it(rest_fmu, fmi_type, method, drift):
    names = ["hammer.s", "piston.s", "breech.s", "hammer.v", "contact.fc"]
    for params in ({}, {"hammer.m": 6000.0}):
        ref = drop_rig(rest=True).simulate(0.01, n_out=11, params=params)
        out = simulate_fmu(rest_fmu, fmi_type=fmi_type, stop_time=0.01, output_interval=1e-3,
                           start_values=params if method is None else {**params, "solver.method": method},
                           output=names)
        for n in ("hammer.s", "piston.s", "breech.s"):
            assert out[n][0] == pytest.approx(ref.initial[n], rel=1e-10), (n, params)
            assert np.ptp(out[n]) < drift
        assert np.max(np.abs(out["hammer.v"])) < 1e-9
        assert out["contact.fc"][0] == pytest.approx(ref["contact.fc"][0], rel=1e-10)


def test_fmu_line_at_the_supply_pressure_it_is_given(line_fmu):
    for p0 in (200e6, 150e6):
        ref = hydraulic_pulse_rig(line=True).simulate(0.02, n_out=201,
                                                      params={"supply.p0": p0})
        out = simulate_fmu(line_fmu, fmi_type="CoSimulation", stop_time=0.02,
                           output_interval=1e-4, start_values={"supply.p0": p0},
                           output=["line.p", "chamber.p"])
        assert out["line.p"][0] == pytest.approx(p0, rel=1e-10)
        peak = np.max(ref["chamber.p"])
        assert np.max(np.abs(out["chamber.p"] - ref["chamber.p"])) < 1e-5 * peak


def test_fmu_refuses_a_start_it_cannot_solve(rest_fmu, capfd):
    # no gravity: nothing presses the hammer on the piston, its position is free
    with pytest.raises(Exception, match="ExitInitializationMode failed"):
        simulate_fmu(rest_fmu, fmi_type="CoSimulation", stop_time=0.01,
                     start_values={"g": 0.0}, output=["hammer.s"], debug_logging=False)
    assert "start values are not finite" in fmu_log_text(capfd.readouterr().out)


def test_fmi3_fmu_solves_the_start_too(tmp_path):
    path = drop_rig(rest=True).export_fmu(tmp_path / "rest3.fmu", fmi_version=3)
    ref = drop_rig(rest=True).simulate(0.01, n_out=11)
    out = simulate_fmu(str(path), fmi_type="ModelExchange", stop_time=0.01,
                       output_interval=1e-3, output=["hammer.s", "hammer.v"])
    assert out["hammer.s"][0] == pytest.approx(ref.initial["hammer.s"], rel=1e-10)
    assert np.max(np.abs(out["hammer.v"])) < 1e-9
