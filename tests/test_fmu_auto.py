"""solver.method auto in the FMU's co-simulation when the importer sets no
stop time: no run length is assumed (the method is the cheapest for each
second of a long run), and the run switches between the explicit method and
BDF at the solvers' own steps: to BDF where the explicit method's steps are
held by stability (a rig at rest, a fast mode that has decayed), back where
BDF's steps turn short against the fastest mode (a blow). One co-simulation
step of 100 s then costs about what the best method costs (it cost 250-500
times BDF's when the method was chosen for the default experiment's 20 ms);
the trajectory does not depend on the communication step, and agrees with
the compiled backend's."""
import time

import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave

import fmu_support as T  # noqa: E402
from pdbfs.fmu import export_fmu
from pdbfs.models import RIGS

ERK, BDF, ADAMS, AUTO = 3, 1, 2, 0
NAMES = ("drop-rest", "hydraulic-pulse", "drop")


@pytest.fixture(scope="module")
def fmus(tmp_path_factory):
    d = tmp_path_factory.mktemp("auto")
    out = {}
    for name in NAMES:
        path = str(export_fmu(RIGS[name]().compile(), d / f"{name}.fmu"))
        md = fmpy.read_model_description(path)
        out[name] = (fmpy.extract(path, str(d / name)), md)
    return out


def run(fmu, method, t_end, h, name="auto", outputs=()):
    """Communication steps of h to t_end with no stop time: (CPU seconds of
    the steps, the outputs after each, the log)."""
    unzipped, md = fmu
    vr = {v.name: v.valueReference for v in md.modelVariables}
    rec = T.Recorder(name)
    rec.clear()
    s = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=name)
    s.instantiate(loggingOn=True, callbacks=rec.callbacks)
    s.setDebugLogging(True, ["logAll", "logEvents", "logStatusError"])
    s.setupExperiment(startTime=0.0)
    s.setInteger([vr["solver.method"], vr["solver.max_num_steps"]], [method, 2 ** 31 - 1])
    s.enterInitializationMode()
    s.exitInitializationMode()
    n = int(round(t_end / h))
    out = np.zeros((n, len(outputs)))
    cpu = time.process_time()
    for k in range(n):
        s.doStep(k * h, h)
        out[k] = s.getReal([vr[o] for o in outputs]) if outputs else ()
    cpu = time.process_time() - cpu
    s.terminate()
    s.freeInstance()
    return cpu, out, [m for *_, m in rec.messages]


@pytest.mark.parametrize("name,state", [("drop-rest", "breech.s"), ("hydraulic-pulse", "chamber.p")])
def test_one_100_s_step_without_stop_time_costs_about_what_the_best_method_costs(fmus, name, state):
    """drop-rest rests (its breech mode is never rung), the valve rig's fast
    mode decays after the pulse: BDF steps over both, the explicit method
    cannot (measured before: 0.25 s and 0.48 s, BDF 1 ms)."""
    fmu = fmus[name]
    cpu = {m: [] for m in (AUTO, ERK, BDF)}
    ends = {}
    for _ in range(3):
        for m in cpu:
            c, out, _ = run(fmu, m, 100.0, 100.0, outputs=(state,))
            cpu[m].append(c)
            ends[m] = out[-1, 0]
    adams, out, _ = run(fmu, ADAMS, 100.0, 100.0, outputs=(state,))
    best = min(min(cpu[ERK]), min(cpu[BDF]), adams)
    assert min(cpu[AUTO]) <= 3 * best + 2e-3, (cpu, adams)
    assert ends[AUTO] == pytest.approx(ends[BDF], rel=1e-6) and ends[AUTO] == pytest.approx(ends[ERK], rel=1e-6)


def test_the_drop_switches_at_the_solvers_steps_not_at_communication_points(fmus):
    """The hammer falls (the breech at rest: BDF), strikes at t = 0.278 s
    (the explicit method again, whose steps BDF's are then far shorter than):
    the same switches and the same numbers at every common communication
    point, whatever the communication step."""
    outs, logs = [], []
    for h in (2.0 ** -10, 2.0 ** -8):         # (communication points in binary: the same times)
        _, out, log = run(fmus["drop"], AUTO, 103 / 256, h, outputs=("hammer.s", "piston.s", "breech.v"))
        outs.append(out)
        logs.append([m for m in log if " from t=" in m])
    assert np.array_equal(outs[0][3::4], outs[1])
    assert logs[0] == logs[1]
    assert [m.split(": ", 1)[1].split(" from")[0] for m in logs[0]] == ["CVODE BDF", "explicit Runge-Kutta 8(5,3)"]
    t_switch = float(logs[0][1].split("from t=")[1].split(" ")[0])
    assert 0.277 < t_switch < 0.2795          # at the blow (0.2784 s)


def test_the_blows_with_switches_are_the_compiled_backends(fmus):
    """auto's run of the drop rig (BDF in the fall, the explicit method from
    the first blow on) against the compiled backend's explicit run at rtol
    1e-12: the hammer's flight after the blows (t >= 0.3 s) within 1e-6 of
    reference's largest magnitude (measured 1e-7: BDF's fall is as accurate
    as the tolerance asks, 3e-8 m, where the explicit method's is exact), the
    piston and the
    breech within 1e-4 of their largest magnitude throughout (the explicit
    method alone: 3e-5, BDF alone 4e-4, the ringing's phase)."""
    names = ("hammer.s", "hammer.v", "piston.s", "piston.v", "breech.s", "breech.v")
    _, out, _ = run(fmus["drop"], AUTO, 0.6, 1e-3, outputs=names)
    t = np.arange(1, 601) * 1e-3
    ref = RIGS["drop"]().simulate(t_out=np.r_[0.0, t], method="erk", backend="c", rtol=1e-12)
    flight = t >= 0.3
    for k, name in enumerate(names):
        r = np.asarray(ref[name])[1:]
        if name.startswith("hammer"):
            assert np.max(np.abs(out[flight, k] - r[flight])) < 1e-6 * np.max(np.abs(r[flight])), name
        else:
            assert np.max(np.abs(out[:, k] - r)) <= 1e-4 * np.max(np.abs(r)), name
