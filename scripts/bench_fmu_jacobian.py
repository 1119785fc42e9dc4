#!/usr/bin/env python3
"""What the FMU's exact directional derivatives buy an implicit Model
Exchange integrator: the paper rig (0-20 ms) by implicit Euler with Newton
iterations, driven through FMPy's low-level FMI 2.0 API, its Jacobian
d der(x) / dx once per step either from fmi2GetDirectionalDerivative (one
call per state, exact) or by forward differences (fmi2SetContinuousStates
and fmi2GetDerivatives per state, what an importer does without them).
FMPy's own CVode driver computes its Jacobian by CVODE's difference
quotients and calls no directional derivative, so this loop is the
measurement. Prints seconds, Newton iterations and the peak pressure.

    python scripts/bench_fmu_jacobian.py [--step 2e-6] [--repeat 3]
"""
from __future__ import annotations

import argparse
import ctypes
import statistics
import tempfile
import time

import numpy as np


def run(fmu: str, exact: bool, h: float, pressure: str, t_end: float = 0.02) -> tuple[float, int, float]:
    import fmpy
    from fmpy.fmi2 import FMU2Model
    md = fmpy.read_model_description(fmu)
    m = FMU2Model(guid=md.guid, unzipDirectory=fmpy.extract(fmu), modelIdentifier=md.modelExchange.modelIdentifier,
                  instanceName="ie")
    by = {v.name: v.valueReference for v in md.modelVariables}
    x_vr = [d.variable.derivative.valueReference for d in md.derivatives]
    dx_vr = [d.variable.valueReference for d in md.derivatives]
    p_vr = by[pressure]
    nx = len(x_vr)
    nominal = np.ones(nx)
    x = np.zeros(nx)
    dx = np.zeros(nx)
    px, pdx = (a.ctypes.data_as(ctypes.POINTER(ctypes.c_double)) for a in (x, dx))
    t0 = time.perf_counter()
    m.instantiate()
    m.setupExperiment(startTime=0.0)
    m.enterInitializationMode()
    m.exitInitializationMode()
    m.enterContinuousTimeMode()
    m.getContinuousStates(px, nx)
    m.getNominalsOfContinuousStates(nominal.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), nx)

    def f(state):
        x[:] = state
        m.setContinuousStates(px, nx)
        m.getDerivatives(pdx, nx)
        return dx.copy()

    unknowns = (ctypes.c_uint * nx)(*dx_vr)
    knowns = [(ctypes.c_uint * 1)(k) for k in x_vr]
    one = (ctypes.c_double * 1)(1.0)
    col = np.zeros(nx)
    pcol = col.ctypes.data_as(ctypes.POINTER(ctypes.c_double))

    def jacobian(state, f0):
        if exact:   # the raw FMI call (FMPy's wrapper would build its arrays on every call)
            x[:] = state
            m.setContinuousStates(px, nx)
            J = np.empty((nx, nx))
            for j in range(nx):
                m.fmi2GetDirectionalDerivative(m.component, unknowns, nx, knowns[j], 1, one, pcol)
                J[:, j] = col
            return J
        J = np.empty((nx, nx))
        for j in range(nx):
            d = 1e-7 * max(abs(state[j]), nominal[j])
            s = state.copy()
            s[j] += d
            J[:, j] = (f(s) - f0) / d
        return J

    t, xn, newton, peak = 0.0, x.copy(), 0, 0.0
    while t < t_end - 0.5 * h:
        t += h
        m.setTime(t)
        y = xn.copy()
        fy = f(y)
        A = np.eye(nx) - h * jacobian(y, fy)
        for _ in range(20):
            r = y - xn - h * fy
            step = np.linalg.solve(A, -r)
            y += step
            newton += 1
            fy = f(y)
            if np.max(np.abs(step) / (1e-8 * np.abs(y) + 1e-10 * nominal)) < 1.0:
                break
        xn = y
        m.completedIntegratorStep()
        peak = max(peak, m.getReal([p_vr])[0])
    m.terminate()
    m.freeInstance()
    return time.perf_counter() - t0, newton, peak


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--step", type=float, default=2e-6)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--rig", default="paper", help="paper or split-piston (4 masses: 14 states)")
    a = ap.parse_args()
    from pdbfs.fmu import export_fmu
    from pdbfs.models import RIGS
    rig = RIGS[a.rig]()
    with tempfile.TemporaryDirectory() as d:
        fmu = str(export_fmu(rig.compile(), f"{d}/rig.fmu"))
        pressure = rig.compile().signals["pressure"]
        runs = {True: [], False: []}
        for _ in range(a.repeat):   # alternated: the machine's load falls on both alike
            for exact in (True, False):
                runs[exact].append(run(fmu, exact, a.step, pressure))
        for exact in (True, False):
            sec = statistics.median(r[0] for r in runs[exact])
            print(f"{a.rig}, {rig.compile().x.numel()} states, "
                  f"{'directional derivatives' if exact else 'forward differences':24s} {sec:7.2f} s  "
                  f"{runs[exact][0][1]} Newton iterations  peak {runs[exact][0][2] / 1e6:.4f} MPa")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
