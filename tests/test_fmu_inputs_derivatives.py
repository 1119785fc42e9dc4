"""The directional (FMI 2.0, 3.0) and adjoint (FMI 3.0) derivatives cover a
rig's inputs as knowns: against central finite differences of the FMU's own
derivatives and outputs in Model Exchange, mid-pulse, for the closed-loop
pulse rig's plant (its input: the valve's opening) and controller (its
input: the measured pressure, which its output follows directly)."""
import ctypes

import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model

import ssp_support as S

T_MID, OPENING = 2e-3, 0.6      # s, 1: mid-rise, the valve part open


def _state_at(kind):
    """The plant's states at T_MID from its own co-simulation with the valve held at OPENING."""
    path = S.fmu_of(kind)
    md = fmpy.read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName="cs")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    if kind == "plant":
        s.setReal([vr["opening"]], [OPENING])
    s.exitInitializationMode()
    for k in range(20):
        s.doStep(k * T_MID / 20, T_MID / 20)
    names = [d.variable.derivative.name for d in md.derivatives]
    x = s.getReal([vr[n] for n in names])
    s.terminate()
    s.freeInstance()
    return names, np.array(x)


class Model:
    """An ME instance at (T_MID, the state there) with its input at ``value``."""

    def __init__(self, kind, version, value):
        path = S.fmu_of(kind, version)
        self.md = fmpy.read_model_description(path)
        by = {v.name: v for v in self.md.modelVariables}
        names, x = _state_at(kind)
        self.v3 = version == 3
        self.u = next(v.valueReference for v in self.md.modelVariables if v.causality == "input")
        self.dx = [by[f"der({n})"].valueReference for n in names]
        self.y = [v.valueReference for v in self.md.modelVariables if v.causality == "output" and v.name not in names]
        cls = FMU3Model if self.v3 else FMU2Model
        self.m = cls(guid=self.md.guid, unzipDirectory=fmpy.extract(path),
                     modelIdentifier=self.md.modelExchange.modelIdentifier, instanceName=f"{kind}{version}")
        self.m.instantiate()
        if not self.v3:
            self.m.setupExperiment(startTime=0.0)
        self.m.enterInitializationMode()
        self.m.exitInitializationMode()
        self.m.setTime(T_MID)
        x = np.ascontiguousarray(x)
        self.m.setContinuousStates(x.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), x.size)
        self.value = value
        self.set(value)

    def set(self, v):
        (self.m.setFloat64 if self.v3 else self.m.setReal)([self.u], [v])

    def f(self):
        vrs = self.dx + self.y
        return np.array(self.m.getFloat64(vrs) if self.v3 else self.m.getReal(vrs))

    def fd(self, h):
        self.set(self.value + h)
        up = self.f()
        self.set(self.value - h)
        down = self.f()
        self.set(self.value)
        return (up - down) / (2 * h)

    def close(self):
        self.m.terminate()
        self.m.freeInstance()


#: the controller's measurement: 1 MPa below the target there, its output inside 0..1
MEASURED = 29e6
CASES = [("plant", 2, OPENING, 1e-6), ("plant", 3, OPENING, 1e-6), ("controller", 2, MEASURED, 1.0),
         ("controller", 3, MEASURED, 1.0)]


@pytest.mark.parametrize("kind, version, value, h", CASES, ids=[f"{c[0]}-{c[1]}" for c in CASES])
def test_derivatives_with_respect_to_an_input_equal_finite_differences(kind, version, value, h):
    m = Model(kind, version, value)
    try:
        fd = m.fd(h)
        assert np.count_nonzero(fd) >= 2          # the input moves derivatives or outputs
        exact = np.array(m.m.getDirectionalDerivative(m.dx + m.y, [m.u], [1.0]))
        scale = 10 * np.finfo(float).eps * np.abs(m.f()) / h + 1e-7 * np.abs(fd)   # rounding, truncation
        assert np.all(np.abs(exact - fd) <= scale + 1e-300), np.max(np.abs(exact - fd) - scale)
        if m.v3:                                  # the adjoint: the same column, seeded by each unknown
            for i, vr in enumerate(m.dx + m.y):
                assert m.m.getAdjointDerivative([vr], [m.u], [1.0])[0] == pytest.approx(exact[i], rel=1e-12,
                                                                                          abs=1e-300)
    finally:
        m.close()


def test_the_controller_output_follows_its_input_directly():
    """The PI controller's command depends on the measurement at once (its
    proportional part): the model structure says so, and the derivative is
    -k where the output is inside its limits."""
    m = Model("controller", 2, MEASURED)
    try:
        by = {v.name: v for v in m.md.modelVariables}
        out = by["pid.y"]
        dep = next(o for o in m.md.outputs if o.variable is out)
        assert by["measured"] in dep.dependencies
        y = m.m.getReal([out.valueReference])[0]
        assert 0 < y < 1, y
        d = m.m.getDirectionalDerivative([out.valueReference], [m.u], [1.0])[0]
        assert d == pytest.approx(-float(by["pid.k"].start), rel=1e-12)
    finally:
        m.close()


def test_event_indicators_list_the_inputs_they_depend_on():
    """FMI 3.0 lists each event indicator's dependencies: the commanded
    valve's stops (opening 0 and 1) are crossed by its input."""
    import xml.etree.ElementTree as ET
    import zipfile
    with zipfile.ZipFile(S.fmu_of("plant", 3)) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    vr = {v.get("name"): v.get("valueReference") for v in root.find("ModelVariables")}
    deps = {e.get("valueReference"): e.get("dependencies").split() for e in root.find("ModelStructure")
            if e.tag == "EventIndicator"}
    assert deps[vr["event.valve.closed"]] == [vr["opening"]] == deps[vr["event.valve.open"]]
    assert deps[vr["event.chamber.cavitation"]] == [vr["chamber.p_law"]]
