"""The FMI state tables for reading and setting variables, FMI 2.0 and 3.0,
through fmpy's low-level API and the raw C calls: a call the table does not
allow in the instance's state is fmi*Error with one log line naming the
function and the state, as for every other out-of-order call.

FMI 2.0 (sections 3.2.3 and 4.2.4) reads no variable in Instantiated; FMI 3.0
reads there only the start values modelDescription.xml declares (the
parameters and the solver settings): everything else is calculated in
Initialization Mode. Integer, Boolean and String are set in Instantiated,
Initialization Mode, Event Mode and between steps (never in Continuous-Time
Mode or once terminated); fmi2SetRealInputDerivatives before the first step
or between steps, fmi2GetRealOutputDerivatives from the first step on."""
import ctypes

import numpy as np
import pytest

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

import fmu_support as T

FMI_ERROR = 3
#: the paper rig's defaults in modelDescription.xml
HAMMER_M, RTOL, MAX_NUM_STEPS = 2948.4, 1e-8, 10_000_000


_UNZIPPED: dict = {}


def _unzip(version, tmp_path_factory):
    """(version, folder, model description, value references) of the paper rig's FMU, unzipped once."""
    if version not in _UNZIPPED:
        path = T.built_fmu("paper", version)
        d = tmp_path_factory.mktemp(f"table{version}")
        extract(path, str(d))
        md = read_model_description(path)
        _UNZIPPED[version] = version, str(d), md, {v.name: v.valueReference for v in md.modelVariables}
    return _UNZIPPED[version]


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def unzipped(request, tmp_path_factory):
    return _unzip(request.param, tmp_path_factory)


@pytest.fixture(scope="module")
def unzipped2(tmp_path_factory):
    return _unzip(2, tmp_path_factory)


@pytest.fixture(scope="module")
def unzipped3(tmp_path_factory):
    return _unzip(3, tmp_path_factory)


class Instance:
    """One instance of either version, its log lines kept."""

    def __init__(self, unzipped, name, kind="cs"):
        self.version, d, md, self.vr = unzipped
        self.name = name
        classes = {2: (FMU2Slave, FMU2Model), 3: (FMU3Slave, FMU3Model)}[self.version]
        self.fmu = classes[kind == "me"](guid=md.guid, unzipDirectory=d,
                                         modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        if self.version == 2:
            self.rec = T.Recorder(name)
            self.fmu.instantiate(callbacks=self.rec.callbacks)
        else:
            self.lines = []
            self.fmu.instantiate(logMessage=lambda env, st, cat, msg: self.lines.append((st, msg.decode())))

    def errors(self) -> list[str]:
        if self.version == 2:
            return self.rec.errors()
        return [m for s, m in self.lines if s >= FMI_ERROR]

    def clear(self):
        self.rec.clear() if self.version == 2 else self.lines.clear()

    def refused(self, fn, *args) -> str:
        """``fn(*args)`` fails with exactly one error line, which is returned."""
        self.clear()
        with pytest.raises(FMICallException):
            fn(*args)
        errs = self.errors()
        assert len(errs) == 1, errs
        return errs[0]

    def raw(self, fname, *args) -> int:
        return T.untyped(self.fmu.dll, fname)(ctypes.c_void_p(self.fmu.component), *args)

    def raw_refused(self, fname, *args) -> str:
        self.clear()
        assert self.raw(fname, *args) == FMI_ERROR
        errs = self.errors()
        assert len(errs) == 1, errs
        return errs[0]

    def get(self, *names):
        get = self.fmu.getReal if self.version == 2 else self.fmu.getFloat64
        return get([self.vr[n] for n in names])

    def enter_init(self):
        if self.version == 2:
            self.fmu.setupExperiment(startTime=0.0, stopTime=0.02)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=0.02)


NONE = (ctypes.c_void_p(None), ctypes.c_size_t(0), ctypes.c_void_p(None))


def test_fmi2_reads_no_variable_before_initialization_mode(unzipped2):
    """fmi2GetReal (also of a parameter), fmi2GetInteger, fmi2GetBoolean and
    fmi2GetString in Instantiated, Co-Simulation and Model Exchange alike;
    from Initialization Mode on the same calls answer."""
    for kind in ("cs", "me"):
        a = Instance(unzipped2, f"early2{kind}", kind)
        for names in (["hammer.m"], ["oil.pressure"], ["hammer.s", "hammer.m"]):
            line = a.refused(a.get, *names)
            assert line == "fmi2GetReal: must not be called in state 'instantiated'", line
        line = a.refused(a.fmu.getInteger, [a.vr["solver.method"]])
        assert line.startswith("fmi2GetInteger: must not be called in state 'instantiated'"), line
        for fname in ("fmi2GetBoolean", "fmi2GetString"):
            assert a.raw_refused(fname, *NONE).startswith(f"{fname}: must not be called in state 'instantiated'")
        a.enter_init()
        assert a.get("hammer.m") == [HAMMER_M] and np.isfinite(a.get("oil.pressure")[0])
        assert a.fmu.getInteger([a.vr["solver.method"]]) == [0]
        assert a.raw("fmi2GetBoolean", *NONE) == 0 and a.raw("fmi2GetString", *NONE) == 0
        a.fmu.freeInstance()


def test_fmi3_reads_start_values_only_before_initialization_mode(unzipped3):
    """In Instantiated FMI 3.0 gives the start values modelDescription.xml
    declares (a parameter as set there too); a calculated variable (an
    output, a state, a derivative, time) is refused, naming it; from
    Initialization Mode on it is there."""
    for kind in ("cs", "me"):
        a = Instance(unzipped3, f"early3{kind}", kind)
        assert a.get("hammer.m", "solver.rtol") == [HAMMER_M, RTOL]
        a.fmu.setFloat64([a.vr["hammer.m"]], [3000.0])
        assert a.get("hammer.m") == [3000.0]
        assert a.fmu.getInt64([a.vr["solver.method"]]) == [0]
        assert a.fmu.getInt32([a.vr["solver.max_num_steps"]]) == [MAX_NUM_STEPS]
        for name, said in (("oil.pressure", "oil.pressure"), ("hammer.s", "state hammer.s"),
                           ("der(hammer.v)", "der(hammer.v)"), ("time", "time")):
            line = a.refused(a.get, "hammer.m", name)
            assert line.startswith(f"fmi3GetFloat64: {said}") and "has no start value" in line, line
        a.enter_init()
        p, s = a.get("oil.pressure", "hammer.s")
        assert np.isfinite(p) and np.isfinite(s)
        a.fmu.freeInstance()


def test_discrete_values_are_set_where_the_table_says(unzipped):
    """Integer, Boolean and String (FMI 3.0: Int32, Int64, Boolean, String)
    are not set once terminated, nor in Continuous-Time Mode; Real input
    derivatives not once terminated, output derivatives not before the first
    step (FMI 2.0). Each with no value references, so that only the state
    decides."""
    version = unzipped[0]
    calls = {2: ("fmi2SetInteger", "fmi2SetBoolean", "fmi2SetString"),
             3: ("fmi3SetInt32", "fmi3SetInt64", "fmi3SetBoolean", "fmi3SetString")}[version]
    args = NONE if version == 2 else (*NONE, ctypes.c_size_t(0))
    a = Instance(unzipped, f"set{version}")
    for fname in calls:
        assert a.raw(fname, *args) == 0                            # Instantiated
    if version == 2:
        out = "fmi2GetRealOutputDerivatives"
        line = a.raw_refused(out, *NONE, ctypes.c_void_p(None))
        assert line == f"{out}: must not be called in state 'instantiated'", line
    a.enter_init()
    a.fmu.exitInitializationMode()
    a.fmu.doStep(0.0, 1e-4)
    for fname in calls:
        assert a.raw(fname, *args) == 0                            # between steps
    a.fmu.terminate()
    for fname in calls:
        line = a.raw_refused(fname, *args)
        assert line == f"{fname}: must not be called in state 'terminated'", line
    if version == 2:
        fname = "fmi2SetRealInputDerivatives"
        line = a.raw_refused(fname, *NONE, ctypes.c_void_p(None))
        assert line == f"{fname}: must not be called in state 'terminated'", line
    a.fmu.freeInstance()
    m = Instance(unzipped, f"setme{version}", "me")
    m.enter_init()
    m.fmu.exitInitializationMode()
    m.fmu.enterContinuousTimeMode()
    for fname in calls:
        line = m.raw_refused(fname, *args)
        assert line == f"{fname}: must not be called in state 'continuous-time mode'", line
    m.fmu.freeInstance()
