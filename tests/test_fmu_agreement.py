"""The FMU (CS and ME through fmpy, CS through libcosimpy and ecospy) agrees
with the CasADi path to 1e-6, and its results do not depend on the
communication step, with or without a stop time."""
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
    """Peak within 1e-6 relative; trajectory within 1e-6 of the peak at
    every reference output point (measured: 3e-7 at most)."""
    t, idx = np.unique(t, return_index=True)  # ME results repeat event instants
    p = np.asarray(p)[idx]
    peak = np.max(np.abs(p_ref))
    assert np.max(np.abs(p)) == pytest.approx(peak, rel=1e-6)
    assert t[0] <= t_ref[0] + 1e-12 and t[-1] >= t_ref[-1] - 1e-12
    err = np.max(np.abs(np.interp(t_ref, t, p) - p_ref))
    assert err < 1e-6 * peak, err / peak


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


def _no_stop_time_run(fmu_path, h, t_end=0.02):
    """oil.pressure on a 1 ms grid, co-simulated in steps of h without a stop
    time (as libcosim and fmusim without --stop-time call the FMU)."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave
    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}["oil.pressure"]
    d = extract(fmu_path)
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName=f"nostop{h}")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)          # no stop time
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    n, every = round(t_end / h), round(1e-3 / h)
    out = [fmu.getReal([vr])[0]]
    for k in range(n):
        fmu.doStep(k * h, h)
        if (k + 1) % every == 0:
            out.append(fmu.getReal([vr])[0])
    fmu.terminate()
    fmu.freeInstance()
    return np.array(out)


def test_no_stop_time_trajectory_is_independent_of_the_step(fmu_path):
    a = _no_stop_time_run(fmu_path, 1e-5)
    b = _no_stop_time_run(fmu_path, 1e-3)
    c = _no_stop_time_run(fmu_path, 2.5e-4)
    peak = np.max(np.abs(a))
    assert np.max(np.abs(a - b)) <= 1e-12 * peak and np.max(np.abs(a - c)) <= 1e-12 * peak


def test_ecospy_agrees_with_casadi(fmu_path, references):
    """Ecos (ecospy from PyPI; needs Debian's libtbb12 and the run bit on its
    bundled ecos and proxyfmu binaries)."""
    import importlib.util
    import os
    spec = importlib.util.find_spec("ecospy")
    if spec is None:
        pytest.skip("ecospy is not installed (pip install ecospy)")
    bins = os.path.join(os.path.dirname(spec.origin), "binaries")
    for exe in ("ecos", "proxyfmu"):
        f = os.path.join(bins, exe)
        if os.path.isfile(f) and not os.access(f, os.X_OK):
            os.chmod(f, os.stat(f).st_mode | 0o111)
    from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure
    EcosLib.set_log_level("warn")
    for case in ("default", "v0=4.23"):
        ss = EcosSimulationStructure()
        ss.add_model("rig", fmu_path)
        ss.add_parameter_set("case", {f"rig::{k}": v for k, v in CASES[case].items()})
        sim = EcosSimulation(structure=ss, step_size=1e-5)
        sim.init(parameter_set="case")
        t, p = [0.0], [sim.get_real("rig::oil.pressure")]
        for _ in range(2000):
            sim.step()
            t.append(sim.get_time())
            p.append(sim.get_real("rig::oil.pressure"))
        sim.terminate()
        sim.free()
        assert_agrees(*references[case], np.array(t), np.array(p))
