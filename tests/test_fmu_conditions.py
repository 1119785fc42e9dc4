"""What pdbfs refuses, the FMU (FMI 2.0 and 3.0) refuses too, with one log
line naming it: a tunable parameter changed during a run to a value that
breaks a component's condition (hydraulic-pulse: valve.t_close >= valve.t_open)
or leaves the model without finite derivatives, and a start value of a state
that index reduction made algebraic (test_index_reduction.CamLine: m2.v is
computed from the cam and the line). A valid change during a run gives what a
fresh Python run with that value from that time gives."""

from collections import Counter

import numpy as np
import pytest

from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model, FMU3Slave

import fmu_support as T
from pdbfs.fmu import export_fmu
from test_index_reduction import DG0, RATIO, V1, CamLine

VERSIONS = [2, 3]
TIGHT = dict(rtol=1e-10, atol=1e-12)


@pytest.fixture(scope="module", params=VERSIONS, ids=["fmi2", "fmi3"])
def pulse(request, tmp_path_factory):
    path = T.built_fmu("pulse", request.param)
    d = tmp_path_factory.mktemp(f"pulse{request.param}")
    extract(path, str(d))
    md = read_model_description(path)
    return request.param, str(d), md, {v.name: v.valueReference for v in md.modelVariables}


class Instance:
    """One instance (co-simulation or model exchange) of either FMI version
    with its log: the error lines of the last call in ``errors``."""

    def __init__(self, unzipped, kind="cs", name="x"):
        self.version, d, md, self.vr = unzipped
        mi = md.coSimulation if kind == "cs" else md.modelExchange
        if self.version == 2:
            cls = FMU2Slave if kind == "cs" else FMU2Model
            self.rec = T.Recorder(name)
            self.fmu = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=mi.modelIdentifier,
                           instanceName=name)
            self.fmu.instantiate(callbacks=self.rec.callbacks)
        else:
            cls = FMU3Slave if kind == "cs" else FMU3Model
            self.messages = []
            self.fmu = cls(guid=md.guid, unzipDirectory=d, modelIdentifier=mi.modelIdentifier,
                           instanceName=name)
            self.fmu.instantiate(logMessage=lambda env, st, cat, msg: self.messages.append((st, msg.decode())))
        self.t = 0.0

    def state(self, name, *args):
        """FMU state calls under either version's name (getFMUstate, getFMUState...)."""
        v2 = {"get": "getFMUstate", "set": "setFMUstate", "ser": "serializeFMUstate",
              "deser": "deSerializeFMUstate"}
        v3 = {"get": "getFMUState", "set": "setFMUState", "ser": "serializeFMUState",
              "deser": "deserializeFMUState"}
        return getattr(self.fmu, (v2 if self.version == 2 else v3)[name])(*args)

    def errors(self):
        if self.version == 2:
            return self.rec.errors()
        return [m for s, m in self.messages if s >= 3]

    def clear(self):
        self.rec.clear() if self.version == 2 else self.messages.clear()

    def set(self, **values):
        names = [k.replace("__", ".") for k in values]
        setter = self.fmu.setReal if self.version == 2 else self.fmu.setFloat64
        setter([self.vr[n] for n in names], list(values.values()))

    def get(self, *names):
        getter = self.fmu.getReal if self.version == 2 else self.fmu.getFloat64
        return np.array(getter([self.vr[n] for n in names]))

    def refused(self, **values):
        """Set ``values``: the call must fail with exactly one error line, returned."""
        self.clear()
        with pytest.raises(FMICallException):
            self.set(**values)
        errs = self.errors()
        assert len(errs) == 1 and "\n" not in errs[0], errs
        return errs[0]

    def init(self, stop=0.02):
        if self.version == 2:
            self.fmu.setupExperiment(startTime=0.0, stopTime=stop)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0, stopTime=stop)
        self.fmu.exitInitializationMode()

    def run(self, t_end, h=1e-4, name="chamber.p"):
        out, t0 = [], self.t
        for k in range(int(round((t_end - t0) / h))):
            self.fmu.doStep(self.t, h)
            self.t = t0 + (k + 1) * h
            out.append(self.get(name)[0])
        return np.array(out)


def test_a_tunable_change_that_breaks_a_condition_is_refused_and_named(pulse):
    """Co-simulation: valve.t_open moved past valve.t_close between steps is
    refused, naming both and the condition; nothing changes, and restoring a
    state (what FMI asks after an error) continues as if it had never been
    tried (the instance keeps its state anyway: FMI 3.0 calls a refused
    argument an error, after which an importer restores a state or resets)."""
    a, b = Instance(pulse, name="bad"), Instance(pulse, name="ref")
    for i in (a, b):
        i.init()
        i.run(0.002)
    saved = a.state("get")
    msg = a.refused(valve__t_open=5e-3)
    assert "valve.t_open = 0.005" in msg and "valve (PulseValve)" in msg
    assert "would start to close before it opens" in msg and "t=0.002" in msg
    msg = a.refused(valve__t_open=5e-3, valve__t_close=4e-3)
    assert "valve.t_open = 0.005, valve.t_close = 0.004" in msg
    assert list(a.get("valve.t_open", "valve.t_close")) == [0.0, 4.5e-3]     # nothing changed
    a.set(valve__t_open=5e-3, valve__t_close=6e-3)     # consistent, in one call: taken
    assert list(a.get("valve.t_open", "valve.t_close")) == [5e-3, 6e-3]
    a.state("set", saved)                              # back to the state before all this
    b.state("set", b.state("get"))      # the same restart of the solver, never refused
    assert np.array_equal(a.run(0.01), b.run(0.01))
    a.fmu.freeInstance()
    b.fmu.freeInstance()


@pytest.mark.parametrize("values,words", [
    ({"valve.t_open": 5e-3}, "valve (PulseValve): the valve would start to close before it opens"),
    ({"supply.p0": 50e6}, "supply (Accumulator): starts below its gas precharge")])
def test_settings_that_break_a_condition_are_refused_at_initialisation(pulse, values, words):
    """Before initialisation parameters are set one at a time; the
    conditions are checked on leaving initialisation (one line), and a reset
    instance runs again."""
    a = Instance(pulse, name="init")
    a.set(**{k.replace(".", "__"): v for k, v in values.items()})
    a.clear()
    with pytest.raises(FMICallException):
        a.init()
    errs = a.errors()
    assert len(errs) == 1 and words in errs[0] and "ExitInitializationMode" in errs[0], errs
    a.fmu.reset()
    a.init()
    assert np.all(np.isfinite(a.run(0.001)))
    a.fmu.freeInstance()


def test_a_tunable_change_that_makes_the_model_infinite_is_refused(pulse):
    """drain.A = 1e308 m2 is within its bounds (> 0) but the drain's flow
    overflows: refused at the set, not integrated into Infinity."""
    a = Instance(pulse, name="inf")
    a.init()
    p = a.run(0.005)
    msg = a.refused(drain__A=1e308)
    assert "drain.A = 1e+308" in msg and "not be finite" in msg
    assert a.get("drain.A")[0] == 4e-5
    assert np.all(np.isfinite(a.run(0.006))) and np.all(np.isfinite(p))
    a.fmu.freeInstance()


def test_model_exchange_refuses_it_in_event_mode(pulse):
    m = Instance(pulse, kind="me", name="me")
    m.init()
    if m.version == 2:
        m.fmu.newDiscreteStates()
    else:
        m.fmu.updateDiscreteStates()
    m.fmu.enterContinuousTimeMode()
    m.fmu.enterEventMode()
    msg = m.refused(valve__t_close=1e-3, valve__t_open=2e-3)
    assert "valve.t_close = 0.001, valve.t_open = 0.002" in msg and "close before it opens" in msg
    m.set(valve__t_close=5e-3)            # a valid change is taken
    assert m.get("valve.t_close")[0] == 5e-3
    m.fmu.freeInstance()


def test_no_value_that_is_not_finite_is_returned_as_ok(pulse):
    """Model Exchange: the importer's state may be one the model cannot run
    at (the accumulator's gas volume at zero, supply.V_oil = V0: an infinite
    pressure): its derivatives and outputs are errors naming them, never NaN
    with status OK."""
    import ctypes
    m = Instance(pulse, kind="me", name="nan")
    m.init()
    x = (ctypes.c_double * 2)(4e-3, 101325.0)          # supply.V_oil = supply.V0, chamber.p_law
    m.fmu.setContinuousStates(x, 2)
    for name in ("der(chamber.p_law)", "supply.p"):
        m.clear()
        with pytest.raises(FMICallException):
            m.get(name)
        errs = m.errors()
        assert len(errs) == 1 and f"{name} = " in errs[0] and ("nan" in errs[0] or "inf" in errs[0]), errs
    m.fmu.freeInstance()


def test_a_valid_tunable_change_runs_as_a_fresh_run_with_that_value(pulse):
    """valve.t_close moved from 4.5 to 6 ms at 3 ms: the valve has not begun to
    close, so the run must be Python's run with t_close = 6 ms from the start
    (its time events moved: the closing starts at 6 ms, not 4.5 ms)."""
    a = Instance(pulse, name="tclose")
    a.init()
    a.run(0.003)
    a.set(valve__t_close=6e-3)
    p = a.run(0.012)
    a.fmu.freeInstance()
    _, rig = T.built_model("pulse")
    ref = rig.simulate(0.012, n_out=121, params={"valve.t_close": 6e-3}, **TIGHT)["chamber.p"][31:]
    old = rig.simulate(0.012, n_out=121, **TIGHT)["chamber.p"][31:]
    peak = np.max(np.abs(ref))
    assert np.max(np.abs(p - ref)) < 1e-6 * peak
    assert np.max(np.abs(old - ref)) > 1e-2 * peak         # the change shows


def test_a_valid_change_acts_from_that_time(pulse):
    """drain.A doubled at 8 ms (the valve shut since 6.5 ms): Python started
    from the state at 8 ms with the doubled drain and the valve kept shut."""
    a = Instance(pulse, name="drain")
    a.init()
    a.run(0.008)
    a.set(drain__A=8e-5)
    p = a.run(0.014)
    a.fmu.freeInstance()
    dae, rig = T.built_model("pulse")
    first = rig.simulate(0.008, n_out=81, **TIGHT)
    x8 = {n: float(first[n][-1]) for n in dae.x_names}
    shut = {"valve.t_open": 1.0, "valve.t_close": 2.0}      # never opens in the second stage
    ref = rig.simulate(0.006, n_out=61, params={"drain.A": 8e-5, **shut}, start=x8, **TIGHT)["chamber.p"][1:]
    same = rig.simulate(0.006, n_out=61, params=shut, start=x8, **TIGHT)["chamber.p"][1:]
    scale = np.max(np.abs(ref))
    assert np.max(np.abs(p - ref)) < 1e-6 * scale
    assert np.max(np.abs(same - ref)) > 1e-2 * scale        # the drain's change shows


def test_a_restored_state_that_breaks_a_condition_is_refused(pulse):
    """A serialised state after initialisation with valve.t_open past
    valve.t_close (a corrupted file) is refused as the set is."""
    a = Instance(pulse, name="ser")
    a.init()
    a.run(0.001)
    ser = bytearray(a.state("ser", a.state("get")))
    k = T.built_model("pulse")[0].p_names.index("valve.t_open")
    off = 4 + 4 + 64 + 4 + 4 + 8 * (1 + k)        # Snapshot: magic, size, token, mode, type, time, p[]
    assert np.frombuffer(bytes(ser[off:off + 8]))[0] == 0.0
    ser[off:off + 8] = np.float64(5e-3).tobytes()
    a.clear()
    with pytest.raises(FMICallException):
        a.state("deser", T.resealed(ser))
    assert any("close before it opens" in e for e in a.errors()), a.errors()
    a.fmu.freeInstance()


# -- a start of a state that index reduction made algebraic -------------------------

@pytest.fixture(scope="module", params=VERSIONS, ids=["fmi2", "fmi3"])
def cam(request, tmp_path_factory):
    rig = CamLine()
    d = tmp_path_factory.mktemp(f"cam{request.param}")
    return request.param, str(export_fmu(rig.compile(), d / "cam.fmu", fmi_version=request.param)), rig


def test_the_reduced_state_is_calculated_not_settable(cam, tmp_path):
    """m2.v is computed from the cam and the line: in modelDescription.xml an
    output with initial="calculated" and no start, and a set is refused; its
    start is the parameter m2.v0, settable, checked at initialisation."""
    version, path, _ = cam
    md = read_model_description(path)
    v = {x.name: x for x in md.modelVariables}
    assert v["m2.v"].initial == "calculated" and v["m2.v"].start is None
    assert v["m2.v0"].causality == "parameter" and v["m2.v0"].initial == "exact"
    assert "start of m2.v" in v["m2.v0"].description and "cam (Cam)" in v["m2.v0"].description
    extract(path, str(tmp_path))
    unzipped = (version, str(tmp_path), md, {x.name: x.valueReference for x in md.modelVariables})
    a = Instance(unzipped, name="camset")
    a.refused(m2__v=1.0)
    a.fmu.freeInstance()


@pytest.mark.parametrize("interface", ["CoSimulation", "ModelExchange"])
@pytest.mark.parametrize("start", [{"m2.v0": 1.0}, {"m1.v0": 2 * V1}], ids=["m2.v0", "m1.v0"])
def test_a_start_the_constraint_overrides_is_refused_at_initialisation(cam, start, interface, capfd):
    version, path, _ = cam
    def said(out=""):
        return [ln for ln in T.fmu_log_text(out).splitlines() if "m2.v starts at" in ln]
    capfd.readouterr()
    before = said()
    with pytest.raises(Exception, match="ExitInitializationMode"):
        simulate_fmu(path, stop_time=0.1, start_values=start, fmi_type=interface)
    lines = list((Counter(said(capfd.readouterr().out)) - Counter(before)).elements())
    assert len(lines) == 1, lines
    assert "cam (Cam), equation 1" in lines[0] and f"fmi{version}ExitInitializationMode" in lines[0]


def test_consistent_starts_are_taken_and_run_as_in_python(cam):
    """m1.v0 and m2.v0 doubled together satisfy the line: the FMU starts m2.v
    there and follows Python's run with the same parameters."""
    _, path, rig = cam
    params = {"m1.v0": 2 * V1, "m2.v0": -RATIO * DG0 * 2 * V1}
    r = simulate_fmu(path, stop_time=0.5, output_interval=5e-3, start_values=params,
                     output=["m1.s", "m2.v"], relative_tolerance=1e-10)
    assert r["m2.v"][0] == pytest.approx(params["m2.v0"], rel=1e-12)
    ref = rig.simulate(0.5, n_out=101, params=params, **TIGHT)
    scale = np.max(np.abs(ref["m1.s"]))
    assert np.max(np.abs(r["m1.s"] - ref["m1.s"])) < 1e-6 * scale
    assert np.max(np.abs(r["m2.v"] - ref["m2.v"])) < 1e-6 * np.max(np.abs(ref["m2.v"]))
