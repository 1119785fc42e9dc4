"""The FMU through fmpy's low-level API: instances, reset, FMU state, misuse."""
import ctypes

import casadi
import numpy as np
import pytest

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave

import fmu_support as T


@pytest.fixture(scope="module")
def unzipped(tmp_path_factory):
    path = T.built_fmu("paper")
    d = tmp_path_factory.mktemp("unzipped")
    extract(path, str(d))
    md = read_model_description(path)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    return str(d), md, vrs


class Inst:
    """An FMU instance with its log recorder."""

    def __init__(self, unzipped, kind="cs", name="a"):
        d, md, self.vr = unzipped
        cls, mi = (FMU2Slave, md.coSimulation) if kind == "cs" else (FMU2Model, md.modelExchange)
        self.rec = T.Recorder(name)
        self.fmu = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=mi.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=self.rec.callbacks)
        self.t = 0.0

    def set(self, **kw):
        self.fmu.setReal([self.vr[k.replace("__", ".")] for k in kw], list(kw.values()))

    def setn(self, name, value):
        self.fmu.setReal([self.vr[name]], [value])

    def get(self, *names):
        return self.fmu.getReal([self.vr[n] for n in names])

    def enter_init(self):
        """Initialization Mode: where FMI 2.0 first lets values be read."""
        self.fmu.setupExperiment(startTime=0.0, stopTime=0.02)
        self.fmu.enterInitializationMode()

    def init(self, tol=None, **params):
        self.fmu.setupExperiment(tolerance=tol, startTime=0.0, stopTime=0.02)
        for k, v in params.items():
            self.setn(k, v)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.t = 0.0

    def run(self, t_end, h=1e-4, names=("oil.pressure", "contact.f", "hammer.v")):
        out = []
        n = int(round((t_end - self.t) / h))
        t0 = self.t
        for k in range(n):
            self.fmu.doStep(self.t, h)
            self.t = t0 + (k + 1) * h
            out.append(self.get(*names))
        return np.array(out)

    def expect_error(self, fn, *args, match=None):
        self.rec.clear()
        with pytest.raises(FMICallException):
            fn(*args)
        errs = self.rec.errors()
        assert errs, "no message through the logger"
        if match:
            assert any(match in e for e in errs), errs
        return errs

    def raw(self, fname, *args):
        """Call an FMI function directly, whatever fmpy wraps: returns the status."""
        f = getattr(self.fmu.dll, fname)
        f.restype = ctypes.c_int
        return f(ctypes.c_void_p(self.fmu.component), *args)

    def raw_error(self, fname, *args, match=None):
        self.rec.clear()
        assert self.raw(fname, *args) == 3  # fmi2Error
        if match:
            assert any(match in e for e in self.rec.errors()), self.rec.errors()

    def vec(self, fname, n):
        arr = (ctypes.c_double * n)()
        assert self.raw(fname, arr, ctypes.c_size_t(n)) == 0
        return np.array(arr)

    def free(self):
        self.fmu.freeInstance()


def test_two_instances_are_independent(unzipped):
    a, b = Inst(unzipped, name="a"), Inst(unzipped, name="b")
    a.init()
    b.init(**{"hammer.v0": 4.23, "seal.c": 2.556e6})
    ra, rb = [], []
    for k in range(200):  # interleaved
        ra.append(a.run(a.t + 1e-4)[-1])
        rb.append(b.run(b.t + 1e-4)[-1])
    ra, rb = np.array(ra), np.array(rb)
    # each equals a run of its own alone
    c = Inst(unzipped, name="c")
    c.init()
    rc = c.run(0.02)
    # (the communication points differ by rounding only: a.t is a running sum)
    assert np.allclose(ra, rc, rtol=1e-9, atol=1e-9 * np.abs(rc).max(axis=0))
    assert abs(rb[:, 0].max() / ra[:, 0].max() - 1) > 0.1  # the other parameters show
    for i in (a, b, c):
        i.free()


def test_reset_gives_identical_second_run(unzipped):
    a = Inst(unzipped)
    a.init(**{"seal.c": 2.556e5})
    r1 = a.run(0.02)
    a.fmu.reset()
    # after reset the parameters are back to their defaults (read from Initialization Mode on)
    a.fmu.setupExperiment(startTime=0.0, stopTime=0.02)
    a.fmu.enterInitializationMode()
    assert a.get("seal.c")[0] == pytest.approx(2.556e4)
    a.setn("seal.c", 2.556e5)
    a.fmu.exitInitializationMode()
    a.t = 0.0
    r2 = a.run(0.02)
    assert np.array_equal(r1, r2)
    a.free()


def test_reset_me(unzipped):
    m = Inst(unzipped, kind="me")
    for _ in range(2):
        m.init()
        x = m.vec("fmi2GetContinuousStates", 6)
        dx = m.vec("fmi2GetDerivatives", 6)
        m.fmu.reset()
    assert x[1] == pytest.approx(2.73) and dx[0] == pytest.approx(2.73)
    m.free()


def test_get_set_and_serialize_state(unzipped):
    a = Inst(unzipped)
    a.init()
    a.run(0.004)
    s = a.fmu.getFMUstate()
    ser = a.fmu.serializeFMUstate(s)
    r_cont = a.run(0.012)
    a.fmu.setFMUstate(s)
    a.t = 0.004
    r1 = a.run(0.012)
    a.fmu.setFMUstate(s)
    a.t = 0.004
    r2 = a.run(0.012)
    assert np.array_equal(r1, r2)  # a restored state always gives the same run
    # and the same trajectory as going on without a restart, to solver accuracy
    peak = np.abs(r_cont[:, 0]).max()
    assert np.max(np.abs(r1[:, 0] - r_cont[:, 0])) < 1e-5 * peak
    s2 = a.fmu.deSerializeFMUstate(ser)
    a.fmu.setFMUstate(s2)
    a.t = 0.004
    r3 = a.run(0.012)
    assert np.array_equal(r1, r3)
    a.fmu.freeFMUstate(s)
    a.fmu.freeFMUstate(s2)
    # a state of another model is refused
    a.expect_error(a.fmu.deSerializeFMUstate, T.resealed(bytes(len(ser))), match="not a state")
    a.free()


def test_tunable_parameter_between_steps(unzipped):
    """seal.c changed at t = 4 ms continues from the state there with the new
    value: the CasADi path started from that state with it, to 1e-6."""
    a = Inst(unzipped, name="a")
    a.init()
    a.run(0.004)
    a.setn("seal.c", 2.556e6)  # tunable: accepted between steps
    ra = a.run(0.014)[:, 0]
    assert a.get("seal.c")[0] == 2.556e6
    a.free()
    dae, rig = T.built_model("paper")
    first = rig.simulate(0.004, n_out=41, rtol=1e-10, atol=1e-12)
    x4 = {n: float(first[n][-1]) for n in dae.x_names}
    ref = rig.simulate(0.01, n_out=101, params={"seal.c": 2.556e6}, start=x4, rtol=1e-10,
                       atol=1e-12)["oil.pressure"][1:]     # the rig does not depend on t itself
    peak = np.max(np.abs(ref))
    assert np.max(np.abs(ra - ref)) < 1e-6 * peak
    # and the change shows: the default seal gives another pulse
    assert np.max(np.abs(ra - rig.simulate(0.014, n_out=141)["oil.pressure"][41:])) > 1e-2 * peak


def test_restored_state_is_validated(unzipped):
    """A serialised state is checked as fmi2SetReal checks values: a corrupted
    parameter, mode or tolerance is refused, naming the fault."""
    a = Inst(unzipped, name="restore")
    a.init()
    a.run(0.002)
    ser = bytearray(a.fmu.serializeFMUstate(a.fmu.getFMUstate()))
    good = a.fmu.deSerializeFMUstate(bytes(ser))
    a.fmu.setFMUstate(good)
    for bad, match in T.corrupted_states(ser):
        a.expect_error(a.fmu.deSerializeFMUstate, bad, match=match)
    # the instance is unharmed
    a.fmu.setFMUstate(good)
    a.t = 0.002
    assert np.all(np.isfinite(a.run(0.004)))
    a.free()


def test_step_past_stop_time_is_an_error(unzipped):
    a = Inst(unzipped, name="stop")
    a.init()                                  # stopTime 0.02
    a.run(0.019, h=1e-3)
    a.expect_error(a.fmu.doStep, a.t, 2e-3, match="stopTime")
    a.fmu.doStep(a.t, 1e-3)                  # up to the stop time is fine
    a.free()


def test_rtol_declaration_and_check_agree(unzipped):
    from pdbfs.fmu.variables import RTOL_MAX, RTOL_MIN
    a = Inst(unzipped, name="rtol")
    a.enter_init()
    for v in (RTOL_MIN, RTOL_MAX):
        a.setn("solver.rtol", v)
        assert a.get("solver.rtol")[0] == v
    for v in (RTOL_MAX * 1.01, 1.0, RTOL_MIN / 2, 0.0):
        a.expect_error(a.setn, "solver.rtol", v, match="solver.rtol")
    a.free()


BAD_VALUES = [
    ("hammer.m", float("nan"), "not finite"),
    ("hammer.m", float("inf"), "not finite"),
    ("hammer.m", 0.0, "positive"),
    ("piston.m", -5.0, "positive"),
    ("seal.c", -1.0, "outside"),
    ("contact.k", float("-inf"), "not finite"),
]


@pytest.mark.parametrize("name,value,msg", BAD_VALUES)
def test_bad_parameter_values_rejected(unzipped, name, value, msg):
    a = Inst(unzipped)
    a.enter_init()
    before = a.get(name)[0]
    a.expect_error(a.setn, name, value, match=msg)
    assert a.get(name)[0] == before  # nothing changed
    # the instance still works
    a.fmu.exitInitializationMode()
    r = a.run(0.002, h=1e-3)
    assert np.all(np.isfinite(r))
    a.free()


def test_misuse(unzipped):
    a = Inst(unzipped)
    b = Inst(unzipped, name="bystander")
    b.init()
    rb1 = b.run(0.005)
    vr = a.vr
    # unknown value references (reading: from Initialization Mode on, below)
    a.expect_error(a.fmu.setReal, [999999], [1.0], match="unknown value reference")
    a.expect_error(a.fmu.setBoolean, [0], [True], match="unknown value reference")
    # outputs and states are not settable
    a.expect_error(a.setn, "oil.pressure", 1.0, match="not settable")
    # calls in the wrong state
    a.expect_error(a.fmu.doStep, 0.0, 1e-3, match="must not be called")
    a.expect_error(a.fmu.exitInitializationMode, match="must not be called")
    a.raw_error("fmi2GetDerivatives", (ctypes.c_double * 6)(), ctypes.c_size_t(6),
                match="not available for Co-Simulation")
    a.expect_error(a.fmu.setupExperiment, 0.0, 0.0, None, match="tolerance")
    a.expect_error(a.fmu.setInteger, [vr["solver.method"]], [7], match="solver.method")
    a.init()
    a.expect_error(a.fmu.getReal, [999999], match="unknown value reference")
    a.expect_error(a.fmu.getInteger, [vr["hammer.m"]], match="unknown value reference")
    a.expect_error(a.fmu.enterInitializationMode, match="must not be called")
    a.expect_error(a.fmu.setupExperiment, None, 0.0, None, match="must not be called")
    # fixed parameters after initialisation: error, never ignored
    dae = T.built_model("paper")[0]
    fixed = [p for p in dae.params if not p.tunable]
    assert fixed, "the rig should have fixed parameters (start values at least)"
    for prm in fixed:
        a.expect_error(a.setn, prm.name, prm.value + 1.0, match="fixed")
        assert a.get(prm.name)[0] == prm.value
    for name in ("solver.rtol", "solver.max_step"):
        a.expect_error(a.setn, name, 1e-3, match="fixed")
    a.expect_error(a.fmu.setInteger, [vr["solver.method"]], [2], match="fixed")
    # doStep arguments
    a.expect_error(a.fmu.doStep, 0.0, 0.0, match="positive")
    a.expect_error(a.fmu.doStep, 0.0, -1e-3, match="positive")
    a.expect_error(a.fmu.doStep, 0.0, float("nan"), match="positive")
    a.expect_error(a.fmu.doStep, 1e-3, 1e-3, match="does not match")
    a.fmu.doStep(0.0, 1e-3)
    a.expect_error(a.fmu.doStep, 0.0, 1e-3, match="does not match")
    a.fmu.doStep(1e-3, 1e-3)
    a.fmu.terminate()
    a.expect_error(a.fmu.doStep, 2e-3, 1e-3, match="must not be called")
    # the bystander is untouched
    b.fmu.reset()
    b.init()
    assert np.array_equal(b.run(0.005), rb1)
    a.free()
    b.free()


def test_wrong_guid_is_refused(unzipped):
    d, md, _ = unzipped
    rec = T.Recorder("guid")
    fmu = FMU2Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=d,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName="guid")
    with pytest.raises(Exception, match="instantiate"):
        fmu.instantiate(callbacks=rec.callbacks)
    assert any("GUID" in e for e in rec.errors())
    fmu.freeLibrary()


def test_me_misuse(unzipped):
    m = Inst(unzipped, kind="me")
    m.expect_error(m.fmu.setTime, 0.0, match="must not be called")
    m.raw_error("fmi2DoStep", ctypes.c_double(0.0), ctypes.c_double(1e-3), ctypes.c_int(1),
                match="not available for Model Exchange")
    m.init()
    m.fmu.enterContinuousTimeMode()
    m.expect_error(m.fmu.setReal, [m.vr["seal.c"]], [1.0], match="event mode")
    m.fmu.enterEventMode()
    m.fmu.setReal([m.vr["seal.c"]], [1.0])  # tunable in event mode
    fixed = next(p for p in T.built_model("paper")[0].params if not p.tunable)
    m.expect_error(m.setn, fixed.name, fixed.value + 1.0, match="fixed")
    m.free()


@pytest.mark.parametrize("method,solver", [(1, "CVODE"), (3, "explicit Runge-Kutta")])
def test_solver_failure_reports_time(unzipped, method, solver):
    a = Inst(unzipped)
    a.fmu.setupExperiment(startTime=0.0)
    a.fmu.setInteger([a.vr["solver.max_num_steps"], a.vr["solver.method"]], [50, method])
    a.fmu.enterInitializationMode()
    a.fmu.exitInitializationMode()
    a.rec.clear()
    with pytest.raises(FMICallException):
        a.fmu.doStep(0.0, 0.02)
    errs = a.rec.errors()
    assert any(f"{solver} failed" in e and "at t=" in e for e in errs), errs
    # only reset or free now
    a.expect_error(a.fmu.doStep, 0.0, 0.02, match="must not be called")
    a.fmu.reset()
    a.init()
    assert np.all(np.isfinite(a.run(0.002, h=1e-3)))
    a.free()


def test_solver_settings(unzipped):
    res = {}
    for method in (1, 2, 3):
        a = Inst(unzipped)
        a.fmu.setupExperiment(startTime=0.0)
        a.fmu.setInteger([a.vr["solver.method"]], [method])
        a.setn("solver.max_step", 1e-5)
        a.setn("solver.rtol", 1e-9)
        a.fmu.enterInitializationMode()
        a.fmu.exitInitializationMode()
        assert a.get("solver.rtol")[0] == 1e-9
        res[method] = a.run(0.02)[:, 0]
        a.free()
    peak = res[1].max()
    for other in (2, 3):   # Adams, explicit Runge-Kutta
        assert abs(res[other].max() / peak - 1) < 1e-5
        assert np.max(np.abs(res[1] - res[other])) < 1e-5 * peak


def test_calculated_parameter(tmp_path):
    """A calculated parameter follows the parameters it is computed from:
    with the Lankarani-Nikravesh law, contact.D = 3 k (1 - e^2) / (4 v_impact)."""
    dae, _ = T.built_model("law")
    path = T.built_fmu("law")
    name = "contact.D"
    assert name in dae.calculated and name not in dae.p_names
    extract(path, str(tmp_path))
    md = read_model_description(path)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    assert {v.name: v.causality for v in md.modelVariables}[name] == "calculatedParameter"
    a = Inst((str(tmp_path), md, vrs), name="calc")
    D = casadi.Function("D", [dae.p], [dae.calculated[name][0]])
    p = dae.p_default()

    def expected():
        k, e, v = (p[dae.p_names.index(n)] for n in ("contact.k", "contact.e", "contact.v_impact"))
        value = float(D(p))
        assert value == pytest.approx(3 * k * (1 - e ** 2) / (4 * v), rel=1e-12)
        return value

    a.fmu.setupExperiment(startTime=0.0)
    a.fmu.enterInitializationMode()
    assert a.get(name)[0] == pytest.approx(expected(), rel=1e-12)
    for prm, factor in (("contact.v_impact", 2.0), ("contact.e", 0.5)):
        p[dae.p_names.index(prm)] *= factor
        a.setn(prm, p[dae.p_names.index(prm)])
    a.fmu.exitInitializationMode()
    assert a.get(name)[0] == pytest.approx(expected(), rel=1e-12)
    # a calculated parameter cannot be set
    a.expect_error(a.setn, name, 1.0)
    # and the FMU simulates with it
    r = a.run(0.002, h=1e-4)
    assert np.all(np.isfinite(r)) and np.abs(r[:, 1]).max() > 1e5  # contact force, N
    a.free()
