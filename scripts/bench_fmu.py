#!/usr/bin/env python3
"""Seconds per simulation of the paper rig (0-20 ms, 2001 output points,
rtol 1e-8) through the CasADi path and through the exported FMU (CS and ME
via fmpy, and CS through fmpy's low-level API without the simulate_fmu
driver), all in one process.  Prints medians and ratios.

    python scripts/bench_fmu.py [--repeat 15]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time

import numpy as np


def timed(fn, repeat):
    fn()  # warm-up (builds, loads)
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts), min(ts)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args()
    import fmpy
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    from pdbfs.fmu import export_fmu
    from pdbfs.native.sundials import find_sundials
    from pdbfs.models import paper_rig

    rig = paper_rig()
    dae = rig.compile()
    print(f"rig: pdbfs.models.paper_rig(), {len(dae.x_names)} states")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        path = export_fmu(dae, f"{tmp}/rig.fmu")
        print(f"export_fmu: {time.perf_counter() - t0:.2f} s")
        unz = extract(str(path), f"{tmp}/x")
        md = read_model_description(str(path))
        s = find_sundials()
        print(f"SUNDIALS {s.version} from {s.origin}")

        results = {}

        def casadi_path():
            res = rig.simulate(0.02, n_out=2001, rtol=1e-8, atol=1e-10)
            results["casadi"] = (np.asarray(res.t), np.asarray(res["oil.pressure"]))

        def fmpy_run(kind):
            def run():
                r = fmpy.simulate_fmu(unz, model_description=md, fmi_type=kind, stop_time=0.02,
                                      output_interval=1e-5, output=["oil.pressure"])
                results[kind] = (r["time"], r["oil.pressure"])
            return run

        vr = {v.name: v.valueReference for v in md.modelVariables}
        slave = FMU2Slave(guid=md.guid, unzipDirectory=unz, modelIdentifier=md.coSimulation.modelIdentifier,
                          instanceName="bench")
        slave.instantiate()

        def lowlevel():
            slave.reset()
            slave.setupExperiment(startTime=0.0, stopTime=0.02)
            slave.enterInitializationMode()
            slave.exitInitializationMode()
            out = np.empty(2001)
            out[0] = slave.getReal([vr["oil.pressure"]])[0]
            for k in range(2000):
                slave.doStep(k * 1e-5, 1e-5)
                out[k + 1] = slave.getReal([vr["oil.pressure"]])[0]
            results["lowlevel"] = (np.linspace(0, 0.02, 2001), out)

        def one_step():
            slave.reset()
            slave.setupExperiment(startTime=0.0, stopTime=0.02)
            slave.enterInitializationMode()
            slave.exitInitializationMode()
            slave.doStep(0.0, 0.02)

        rows = [("CasADi path (rig.simulate / cvodes)", casadi_path),
                ("FMU CS via fmpy.simulate_fmu", fmpy_run("CoSimulation")),
                ("FMU ME via fmpy.simulate_fmu (fmpy's CVode)", fmpy_run("ModelExchange")),
                ("FMU CS, fmpy low-level doStep loop", lowlevel),
                ("FMU CS, one fmi2DoStep over 20 ms (solver only)", one_step)]
        times = {}
        for name, fn in rows:
            times[name] = timed(fn, args.repeat)
        slave.terminate()
        slave.freeInstance()
        base = times[rows[0][0]][0]
        print(f"\n{'path':52s} {'median ms':>10s} {'min ms':>8s} {'ratio':>7s}")
        for name, _ in rows:
            med, mn = times[name]
            print(f"{name:52s} {med * 1e3:10.2f} {mn * 1e3:8.2f} {med / base:7.2f}")
        tr, pr = results["casadi"]
        for k in ("CoSimulation", "ModelExchange", "lowlevel"):
            t, p = results[k]
            t, i = np.unique(t, return_index=True)
            err = np.max(np.abs(np.interp(tr, t, np.asarray(p)[i]) - pr)) / np.max(pr)
            print(f"max |p - p_casadi| / peak, {k}: {err:.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
