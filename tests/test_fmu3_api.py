"""The FMI 3.0 FMU through fmpy's low-level API (FMU3Slave, FMU3Model):
misuse is answered by fmi3Error and a log line, as in the 2.0 FMU; FMU
state, reset, tunable parameters, time and event indicators."""
import ctypes

import numpy as np
import pytest

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

import fmu_support as T


@pytest.fixture(scope="module")
def unzipped(tmp_path_factory):
    path = T.built_fmu3("paper")
    d = tmp_path_factory.mktemp("unzipped3")
    extract(path, str(d))
    md = read_model_description(path)
    return str(d), md, {v.name: v.valueReference for v in md.modelVariables}


class Inst3:
    """An FMI 3.0 instance that records its log messages."""

    def __init__(self, unzipped, kind="cs", name="a", token=None):
        d, md, self.vr = unzipped
        self.messages = []
        cls = FMU3Slave if kind == "cs" else FMU3Model
        self.fmu = cls(guid=token or md.guid, unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                       instanceName=name)
        self.fmu.instantiate(logMessage=self.log)
        self.t = 0.0

    def log(self, env, status, category, message):
        self.messages.append((status, category.decode(), message.decode()))

    def errors(self):
        return [m for s, _, m in self.messages if s >= 3]

    def expect_error(self, fn, *args, match):
        self.messages.clear()
        with pytest.raises(FMICallException):
            fn(*args)
        errs = self.errors()
        assert any(match in e for e in errs), errs
        return errs

    def setn(self, name, value):
        self.fmu.setFloat64([self.vr[name]], [value])

    def get(self, *names):
        return self.fmu.getFloat64([self.vr[n] for n in names])

    def init(self, **params):
        for k, v in params.items():
            self.setn(k, v)
        self.fmu.enterInitializationMode(startTime=0.0, stopTime=0.02)
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def run(self, t_end, h=1e-4, names=("oil.pressure", "contact.f", "hammer.v")):
        out, n, t0 = [], int(round((t_end - self.t) / h)), self.t
        for k in range(n):
            event, terminate, early, last = self.fmu.doStep(self.t, h)
            self.t = t0 + (k + 1) * h
            assert not (event or terminate or early) and last == pytest.approx(self.t, rel=1e-12)
            out.append(self.get(*names))
        return np.array(out)


def test_wrong_instantiation_token_is_refused(unzipped):
    for kind in ("cs", "me"):
        with pytest.raises(Exception, match="instantiate"):
            Inst3(unzipped, kind=kind, name="token", token="{00000000-0000-0000-0000-000000000000}")
    # the log line comes through the host's logger before there is an instance
    d, md, _ = unzipped
    seen = []
    fmu = FMU3Slave(guid="{not-this-one}", unzipDirectory=d, modelIdentifier=md.coSimulation.modelIdentifier,
                    instanceName="token")
    with pytest.raises(Exception, match="instantiate"):
        fmu.instantiate(logMessage=lambda env, st, cat, msg: seen.append((st, msg.decode())))
    assert any(st == 3 and "instantiationToken does not match" in m for st, m in seen), seen
    fmu.freeLibrary()


def test_misuse_is_an_error_with_a_log_line(unzipped):
    a = Inst3(unzipped)
    vr = a.vr
    # doStep before initialisation
    a.expect_error(a.fmu.doStep, 0.0, 1e-3, match="fmi3DoStep: must not be called in state 'instantiated'")
    # unknown value references, for every type
    a.expect_error(a.fmu.getFloat64, [999999], match="unknown value reference 999999")
    a.expect_error(a.fmu.setFloat64, [999999], [1.0], match="unknown value reference")
    a.expect_error(a.fmu.getInt32, [vr["hammer.m"]], match="unknown value reference")
    a.expect_error(a.fmu.getInt64, [vr["solver.max_num_steps"]], match="unknown value reference")
    a.expect_error(a.fmu.getBoolean, [0], match="unknown value reference")
    a.expect_error(a.fmu.setString, [0], ["x"], match="unknown value reference")
    # read-only variables and bad values
    for name in ("oil.pressure", "time", "event.oil.compression"):
        a.expect_error(a.setn, name, 1.0, match="not settable")
    a.expect_error(a.setn, "hammer.m", float("nan"), match="not finite")
    a.expect_error(a.setn, "piston.m", -5.0, match="positive")
    a.expect_error(a.fmu.setInt64, [vr["solver.method"]], [7], match="solver.method")
    a.expect_error(a.fmu.enterInitializationMode, 0.0, 0.0, None, match="tolerance")
    # Model Exchange calls on a Co-Simulation instance, and no event mode
    a.expect_error(a.fmu.enterEventMode, match="not available for Co-Simulation")
    a.expect_error(a.fmu.enterStepMode, match="no event mode")
    a.init()
    # fixed parameters after initialisation
    fixed = next(p for p in T.built_model("paper")[0].params if not p.tunable)
    a.expect_error(a.setn, fixed.name, fixed.value + 1.0, match="fixed")
    a.expect_error(a.fmu.setInt32, [vr["solver.max_num_steps"]], [5], match="fixed")
    # doStep arguments
    a.expect_error(a.fmu.doStep, 0.0, -1e-3, match="positive")
    a.expect_error(a.fmu.doStep, 1e-3, 1e-3, match="does not match")
    a.fmu.doStep(0.0, 1e-3)
    a.fmu.terminate()
    a.expect_error(a.fmu.doStep, 1e-3, 1e-3, match="must not be called in state 'terminated'")
    a.fmu.freeInstance()


def test_me_misuse(unzipped):
    m = Inst3(unzipped, kind="me", name="me")
    m.expect_error(m.fmu.setTime, 0.0, match="must not be called")
    arr = (ctypes.c_double * 6)()
    m.expect_error(m.fmu.getContinuousStateDerivatives, arr, 6, match="must not be called")
    m.init()
    m.expect_error(m.fmu.getContinuousStateDerivatives, arr, 5, match="expected 6")
    m.fmu.updateDiscreteStates()
    m.fmu.enterContinuousTimeMode()
    m.expect_error(m.setn, "seal.c", 1.0, match="event mode")
    m.fmu.enterEventMode()
    m.setn("seal.c", 1.0)  # tunable in event mode
    m.fmu.freeInstance()


def test_me_quantities(unzipped):
    """States, derivatives and event indicators by the ME calls and as variables."""
    m = Inst3(unzipped, kind="me", name="me2")
    m.init()
    dae = T.built_model("paper")[0]
    assert m.fmu.getNumberOfContinuousStates() == 6 and m.fmu.getNumberOfEventIndicators() == 3
    x, dx, e = (ctypes.c_double * 6)(), (ctypes.c_double * 6)(), (ctypes.c_double * 3)()
    m.fmu.getContinuousStates(x, 6)
    m.fmu.getContinuousStateDerivatives(dx, 6)
    assert x[1] == pytest.approx(2.73) and dx[0] == pytest.approx(2.73)
    m.fmu.updateDiscreteStates()
    m.fmu.enterContinuousTimeMode()
    m.fmu.setTime(1e-3)
    xs = list(x)
    xs[0] += 1e-4  # the hammer 0.1 mm into the piston
    m.fmu.setContinuousStates((ctypes.c_double * 6)(*xs), 6)
    m.fmu.getEventIndicators(e, 3)
    names = [f"event.{n}" for n in dae.event_names]
    assert list(e) == m.get(*names)
    assert e[0] == pytest.approx(1e-4) and m.get("time") == [1e-3]
    assert m.get("contact.f")[0] < 0  # in contact: the spring pushes
    m.fmu.freeInstance()


def test_state_serialisation_and_reset(unzipped):
    a = Inst3(unzipped, name="state")
    a.init()
    a.run(0.004)
    s = a.fmu.getFMUState()
    ser = a.fmu.serializeFMUState(s)
    r_cont = a.run(0.012)
    a.fmu.setFMUState(s)
    a.t = 0.004
    r1 = a.run(0.012)
    # CVODE restarts from a restored state: the same trajectory to solver accuracy
    assert np.max(np.abs(r1[:, 0] - r_cont[:, 0])) < 1e-5 * np.abs(r_cont[:, 0]).max()
    a.fmu.setFMUState(s)
    a.t = 0.004
    assert np.array_equal(a.run(0.012), r1)  # and always the same one
    s2 = a.fmu.deserializeFMUState(ser)
    a.fmu.setFMUState(s2)
    a.t = 0.004
    assert np.array_equal(a.run(0.012), r1)
    a.fmu.freeFMUState(s)
    a.fmu.freeFMUState(s2)
    a.expect_error(a.fmu.deserializeFMUState, T.resealed(bytes(len(ser))), match="not a state")
    # reset: the second run is the first again
    a.fmu.reset()
    a.init(**{"seal.c": 2.556e5})
    r2 = a.run(0.01)
    a.fmu.reset()
    assert a.get("seal.c")[0] == pytest.approx(2.556e4)
    a.init(**{"seal.c": 2.556e5})
    assert np.array_equal(a.run(0.01), r2)
    a.fmu.freeInstance()


def test_tunable_parameter_between_steps_matches_fmi2(unzipped, tmp_path):
    """A tunable parameter changed between steps restarts CVODE: the 3.0
    FMU gives the 2.0 FMU's numbers (the same loop)."""
    path2 = T.built_fmu("paper")
    extract(path2, str(tmp_path))
    md2 = read_model_description(path2)
    vr2 = {v.name: v.valueReference for v in md2.modelVariables}
    b = FMU2Slave(guid=md2.guid, unzipDirectory=str(tmp_path), modelIdentifier=md2.coSimulation.modelIdentifier,
                  instanceName="fmi2")
    b.instantiate(callbacks=T.Recorder("fmi2").callbacks)
    b.setupExperiment(startTime=0.0, stopTime=0.02)
    b.enterInitializationMode()
    b.exitInitializationMode()
    a = Inst3(unzipped, name="fmi3")
    a.init()
    names = ("oil.pressure", "contact.f", "hammer.v")
    rb, t = [], 0.0
    for k in range(100):
        if k == 40:
            b.setReal([vr2["seal.c"]], [2.556e6])
            a.run(0.004)
            a.setn("seal.c", 2.556e6)
        b.doStep(t, 1e-4)
        t = (k + 1) * 1e-4
        rb.append(b.getReal([vr2[n] for n in names]))
    ra, rb = a.run(0.01, names=names), np.array(rb)[40:]
    assert np.allclose(ra, rb, rtol=1e-9, atol=1e-9 * np.abs(rb).max(axis=0))
    assert a.get("seal.c") == [2.556e6]
    a.fmu.freeInstance()
    b.freeInstance()


def test_issue14_checks_hold_in_fmi3(unzipped):
    """The checks of the version-neutral C answer FMI 3.0 calls as they do
    FMI 2.0 ones: a step past stopTime, solver.rtol outside its declared
    range, a deserialised state with a corrupted parameter or mode."""
    from pdbfs.fmu.variables import RTOL_MAX, RTOL_MIN
    md = unzipped[1]
    rtol = next(v for v in md.modelVariables if v.name == "solver.rtol")
    assert (float(rtol.min), float(rtol.max)) == (RTOL_MIN, RTOL_MAX)
    a = Inst3(unzipped, name="checks")
    a.setn("solver.rtol", RTOL_MIN)
    assert a.get("solver.rtol")[0] == RTOL_MIN
    for v in (RTOL_MAX * 1.01, RTOL_MIN / 2):
        a.expect_error(a.setn, "solver.rtol", v, match="solver.rtol")
    a.setn("solver.rtol", 1e-8)
    a.init()                                  # stopTime 0.02
    a.run(0.002, h=1e-3)
    ser = bytearray(a.fmu.serializeFMUState(a.fmu.getFMUState()))
    for bad, match in T.corrupted_states(ser):
        a.expect_error(a.fmu.deserializeFMUState, bad, match=match)
    a.run(0.019, h=1e-3)
    a.expect_error(a.fmu.doStep, a.t, 2e-3, match="stopTime")
    a.fmu.doStep(a.t, 1e-3)                   # up to the stop time is fine
    a.fmu.freeInstance()
