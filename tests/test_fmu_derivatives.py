"""Exact directional (FMI 2.0, 3.0) and adjoint (FMI 3.0) derivatives of the
state derivatives and outputs with respect to the states and the tunable
parameters (issue 24), against central finite differences of the FMU's own
fmi2GetDerivatives / fmi2GetReal in FMPy, mid-blow where the model is smooth;
the ModelStructure's dependencies hold every nonzero."""
import ctypes
import xml.etree.ElementTree as ET
import zipfile

import fmpy
import numpy as np
import pytest
from fmpy.fmi2 import FMU2Model, FMU2Slave
from fmpy.fmi3 import FMU3Model

import fmu_support as T

T_MID = 3e-3   # mid-blow: contact and column loaded, away from every switch


def _mid_blow_state(kind, md2):
    """The state at T_MID from the FMU's own co-simulation."""
    s = FMU2Slave(guid=md2.guid, unzipDirectory=fmpy.extract(T.built_fmu(kind)),
                  modelIdentifier=md2.coSimulation.modelIdentifier, instanceName="cs")
    s.instantiate()
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    for k in range(30):
        s.doStep(k * T_MID / 30, T_MID / 30)
    names = [d.variable.derivative.name for d in md2.derivatives]
    by = {v.name: v for v in md2.modelVariables}
    x = s.getReal([by[n].valueReference for n in names])
    s.terminate()
    s.freeInstance()
    return names, np.array(x)


class Model:
    """The ME instance of one FMI version with f = [der(x); outputs] at (T_MID, x)."""

    def __init__(self, kind, fmi_version):
        fmu = T.built_fmu(kind, fmi_version)
        md = fmpy.read_model_description(fmu)
        md2 = fmpy.read_model_description(T.built_fmu(kind))
        self.x_names, x = _mid_blow_state(kind, md2)
        by = {v.name: v for v in md.modelVariables}
        self.md, self.by, self.v3 = md, by, fmi_version == 3
        self.x_vr = [by[n].valueReference for n in self.x_names]
        self.dx_vr = [by[f"der({n})"].valueReference for n in self.x_names]
        self.y_vr = [v.valueReference for v in md.modelVariables if v.causality == "output"
                     and v.name not in self.x_names]
        self.p_vr = [v.valueReference for v in md.modelVariables if v.causality == "parameter"
                     and v.variability == "tunable" and v.type in ("Real", "Float64")]
        cls = FMU3Model if self.v3 else FMU2Model
        self.m = cls(guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.modelExchange.modelIdentifier,
                     instanceName=f"d{fmi_version}")
        self.m.instantiate()
        if not self.v3:
            self.m.setupExperiment(startTime=0.0)
        self.m.enterInitializationMode()
        self.m.exitInitializationMode()
        self.m.setTime(T_MID)
        self.x = x
        self.set_x(x)

    def get(self, vrs):
        return np.array(self.m.getFloat64(vrs) if self.v3 else self.m.getReal(vrs))

    def set(self, vrs, values):
        (self.m.setFloat64 if self.v3 else self.m.setReal)(vrs, list(values))

    def set_x(self, x):
        x = np.ascontiguousarray(x, dtype=float)
        self.m.setContinuousStates(x.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), x.size)

    def f(self):
        return self.get(self.dx_vr + self.y_vr)

    def fd_column(self, vr, value):
        h = 1e-6 * max(abs(value), 1e-3)
        if vr in self.x_vr:     # states through fmi2SetContinuousStates
            e = np.zeros(len(self.x))
            e[self.x_vr.index(vr)] = h
            put = lambda d: self.set_x(self.x + d * e / h)  # noqa: E731
        else:
            put = lambda d: self.set([vr], [value + d])  # noqa: E731
        var = next((v for v in self.md.modelVariables if v.valueReference == vr), None)
        low = var.min if var is not None and var.causality == "parameter" and var.min is not None else None
        put(h)
        up = self.f()
        if low is not None and value - h < float(low):   # at its bound: one-sided, second order
            put(2 * h)
            up2 = self.f()
            put(0.0)
            return (4 * up - up2 - 3 * self.f()) / (2 * h)
        put(-h)
        down = self.f()
        put(0.0)
        return (up - down) / (2 * h)

    def fd_jacobian(self):
        """(knowns, J by central differences, E: J's error bound at 1e-6 plus
        the differences' rounding, eps |f_i| / h_j, where a known barely
        moves an unknown)"""
        knowns = self.x_vr + self.p_vr
        values = self.get(knowns)
        J = np.column_stack([self.fd_column(vr, v) for vr, v in zip(knowns, values)])
        h = np.array([1e-6 * max(abs(v), 1e-3) for v in values])
        E = 1e-6 * np.abs(J) + 10 * np.finfo(float).eps * np.abs(self.f())[:, None] / h[None, :]
        return knowns, J, E

    def directional(self, knowns, seed):
        return np.array(self.m.getDirectionalDerivative(self.dx_vr + self.y_vr, knowns, list(seed)))

    def close(self):
        self.m.terminate()
        self.m.freeInstance()


@pytest.fixture(scope="module", params=[("paper", 2), ("paper", 3), ("hydraulic", 3)],
                ids=["paper-2", "paper-3", "hydraulic-3"])
def model(request):
    m = Model(*request.param)
    yield m
    m.close()


def _close(exact, fd, bound):
    assert np.all(np.abs(exact - fd) <= bound), np.max(np.abs(exact - fd) / (bound + 1e-300))


def test_directional_derivatives_equal_finite_differences(model):
    knowns, J, E = model.fd_jacobian()
    assert J.shape[1] == len(model.x_vr) + len(model.p_vr) >= 10 and np.count_nonzero(J) > 20
    # the bound is 1e-6 relative wherever the differences resolve the entry
    assert np.count_nonzero(E <= 2e-6 * np.abs(J)) > 20
    # column by column: one known, seed 1
    cols = np.column_stack([model.directional([k], [1.0]) for k in knowns])
    _close(cols, J, E)
    # any seed over all knowns at once
    v = np.random.default_rng(1).standard_normal(len(knowns))
    _close(model.directional(knowns, v), J @ v, E @ np.abs(v))


def test_adjoint_derivatives_equal_finite_differences(model):
    if not model.v3:
        pytest.skip("fmi3GetAdjointDerivative: FMI 3.0 only")
    knowns, J, E = model.fd_jacobian()
    w = np.random.default_rng(2).standard_normal(J.shape[0])
    got = np.array(model.m.getAdjointDerivative(model.dx_vr + model.y_vr, knowns, list(w), len(knowns)))
    _close(got, J.T @ w, E.T @ np.abs(w))
    # and row by row: the adjoint of each unknown is the FD Jacobian's row
    for i, u in enumerate(model.dx_vr + model.y_vr):
        row = np.array(model.m.getAdjointDerivative([u], knowns, [1.0], len(knowns)))
        _close(row, J[i], E[i])


def test_model_structure_holds_every_nonzero(model):
    knowns, J, _ = model.fd_jacobian()
    nx = len(model.x_vr)
    by_vr = {v.valueReference: v for v in model.md.modelVariables}
    listed = {u.variable.valueReference: {d.valueReference for d in (u.dependencies or [])}
              for u in list(model.md.derivatives) + list(model.md.outputs)}
    assert set(model.dx_vr) <= set(listed) and len(listed) > len(model.dx_vr)
    for i, vr in enumerate(model.dx_vr + model.y_vr):
        if vr not in listed:
            continue
        nonzero = {knowns[j] for j in range(nx) if J[i, j] != 0.0}
        assert nonzero <= listed[vr], (by_vr[vr].name, nonzero - listed[vr])


def test_a_fixed_parameter_is_refused(model):
    fixed = next(v for v in model.md.modelVariables if v.causality == "parameter" and v.variability == "fixed"
                 and v.type in ("Real", "Float64") and not v.name.startswith("solver."))
    with pytest.raises(Exception):
        model.directional([fixed.valueReference], [1.0])


@pytest.mark.parametrize("fmi_version", [2, 3])
def test_declared(fmi_version):
    md = fmpy.read_model_description(T.built_fmu("paper", fmi_version))
    if fmi_version == 2:
        assert md.modelExchange.providesDirectionalDerivative and md.coSimulation.providesDirectionalDerivative
    else:   # (FMPy 0.3.32 looks for 2.0's singular name in a 3.0 FMU: read the XML)
        with zipfile.ZipFile(T.built_fmu("paper", 3)) as z:
            root = ET.fromstring(z.read("modelDescription.xml"))
        for tag in ("ModelExchange", "CoSimulation"):
            i = root.find(tag)
            assert i.get("providesDirectionalDerivatives") == i.get("providesAdjointDerivatives") == "true"
