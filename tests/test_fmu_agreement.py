"""The FMU (CS and ME through fmpy, CS through libcosimpy) agrees with the
CasADi path, and its results do not depend on the communication step."""
import numpy as np
import pytest

import fmpy

import fmu_support as T  # noqa: E402

CASES = {
    "default": {},
    "v0=4.23": {"hammer.v0": 4.23},
    "c2=2.556e6": {"seal.c": 2.556e6},
}


@pytest.fixture(scope="module")
def fmu_path():
    return T.built_fmu("paper")


@pytest.fixture(scope="module")
def references():
    _, rig = T.built_model("paper")
    return {k: T.reference_pressure(rig, p) for k, p in CASES.items()}


def assert_agrees(t_ref, p_ref, t, p):
    """Peak within 1e-4 relative; trajectory within 1e-3 of the peak at
    every reference output point."""
    t, idx = np.unique(t, return_index=True)  # ME results repeat event instants
    p = np.asarray(p)[idx]
    peak = np.max(np.abs(p_ref))
    assert np.max(np.abs(p)) == pytest.approx(peak, rel=1e-4)
    assert t[0] <= t_ref[0] + 1e-12 and t[-1] >= t_ref[-1] - 1e-12
    err = np.max(np.abs(np.interp(t_ref, t, p) - p_ref))
    assert err < 1e-3 * peak, err / peak


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("fmi_type", ["CoSimulation", "ModelExchange"])
def test_fmpy_agrees_with_casadi(fmu_path, references, case, fmi_type):
    r = fmpy.simulate_fmu(fmu_path, fmi_type=fmi_type, start_values=CASES[case], stop_time=0.02,
                          output_interval=1e-5, output=["oil.pressure"])
    assert_agrees(*references[case], r["time"], r["oil.pressure"])


def test_adams_agrees_with_casadi(fmu_path, references):
    r = fmpy.simulate_fmu(fmu_path, fmi_type="CoSimulation", start_values={"solver.method": 2},
                          stop_time=0.02, output_interval=1e-5, output=["oil.pressure"])
    assert_agrees(*references["default"], r["time"], r["oil.pressure"])


@pytest.mark.parametrize("fine,coarse", [(1e-5, 1e-3), (1e-6, 1e-2)])
def test_communication_step_independence(fmu_path, fine, coarse):
    names = ["oil.pressure", "hammer.v", "piston.s"]
    a = fmpy.simulate_fmu(fmu_path, fmi_type="CoSimulation", stop_time=0.02, output_interval=fine, output=names)
    b = fmpy.simulate_fmu(fmu_path, fmi_type="CoSimulation", stop_time=0.02, output_interval=coarse,
                          output=names)
    assert len(b) == round(0.02 / coarse) + 1
    idx = np.searchsorted(a["time"], b["time"] - 0.5 * fine)
    assert np.allclose(a["time"][idx], b["time"], rtol=0, atol=1e-12)
    for n in names:
        scale = np.max(np.abs(a[n]))
        assert np.max(np.abs(a[n][idx] - b[n])) <= 1e-9 * scale, n


def test_libcosimpy_agrees_with_casadi(fmu_path, references):
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    for case in ("default", "v0=4.23"):
        ex = CosimExecution.from_step_size(10_000)  # 10 us, in ns
        idx = ex.add_local_slave(CosimLocalSlave(fmu_path=fmu_path, instance_name="rig"))
        vrs = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}
        for k, v in CASES[case].items():
            ex.real_initial_value(idx, vrs[k], v)
        obs = CosimObserver.create_time_series()
        ex.add_observer(obs)
        assert obs.start_time_series(idx, vrs["oil.pressure"], CosimVariableType.REAL)
        assert ex.simulate_until(20_000_000)
        tp, _, vals = obs.time_series_real_samples(idx, vrs["oil.pressure"], from_step=0, sample_count=2100)
        t = np.array(tp) * 1e-9
        t_ref, p_ref = references[case]
        keep = t_ref <= t[-1] + 1e-12
        assert t[-1] >= 0.0199
        assert_agrees(t_ref[keep], p_ref[keep], t, np.array(vals))
