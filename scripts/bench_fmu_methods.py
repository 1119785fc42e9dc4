#!/usr/bin/env python3
"""Milliseconds per co-simulation run of an exported FMU, by solver.method
(the explicit Runge-Kutta method against CVODE's BDF and Adams, and auto),
in one process, interleaved (each round times every method once, in turn),
median per method:

* ``fmpy.simulate_fmu`` (CS, 0-20 ms, 2001 output points: what a user runs);
* one fmi2DoStep over the whole run (the solver alone, fmpy's loop aside).

The paper rig's peak on the grid is compared with a tight event-located
reference (tests/paper_equations.py); the valve rig (hydraulic_pulse_rig,
four switch times, 0-50 ms) is timed too.

    python scripts/bench_fmu_methods.py [--rounds 15] [--rtol 1e-8]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from paper_equations import TABLE1, pressure, reference  # noqa: E402

METHODS = {"ERK": 3, "BDF": 1, "Adams": 2, "auto": 0}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--rtol", type=float, default=1e-8)
    args = ap.parse_args()
    import fmpy
    from fmpy.fmi2 import FMU2Slave

    from pdbfs.fmu import export_fmu
    from pdbfs.models import hydraulic_pulse_rig, paper_rig

    rigs = {"paper": (paper_rig(), 0.02, "oil.pressure"), "valve": (hydraulic_pulse_rig(), 0.05, "chamber.p")}
    grid = np.linspace(0.0, 0.02, 2001)
    tight = pressure(reference(grid)[0], TABLE1)
    with tempfile.TemporaryDirectory() as tmp:
        runs, times, peaks = {}, {}, {}
        for name, (rig, t_end, out) in rigs.items():
            path = str(export_fmu(rig.compile(), f"{tmp}/{name}.fmu"))
            unz = fmpy.extract(path, f"{tmp}/{name}")
            md = fmpy.read_model_description(path)
            vr = {v.name: v.valueReference for v in md.modelVariables}
            slave = FMU2Slave(guid=md.guid, unzipDirectory=unz, modelIdentifier=md.coSimulation.modelIdentifier,
                              instanceName=name)
            slave.instantiate()
            for meth, code in METHODS.items():
                sv = {"solver.method": code, "solver.rtol": args.rtol}

                def simulate(name=name, unz=unz, md=md, sv=sv, t_end=t_end, out=out, meth=meth):
                    r = fmpy.simulate_fmu(unz, model_description=md, fmi_type="CoSimulation", start_values=sv,
                                          stop_time=t_end, output_interval=t_end / 2000, output=[out])
                    peaks[name, meth] = r[out]

                def one_step(slave=slave, vr=vr, code=code, t_end=t_end):
                    slave.reset()
                    slave.setupExperiment(startTime=0.0, stopTime=t_end)
                    slave.setInteger([vr["solver.method"]], [code])
                    slave.setReal([vr["solver.rtol"]], [args.rtol])
                    slave.enterInitializationMode()
                    slave.exitInitializationMode()
                    slave.doStep(0.0, t_end)
                runs[name, meth, "simulate_fmu"] = simulate
                runs[name, meth, "one doStep"] = one_step
        for fn in runs.values():   # warm-up: loads
            fn()
        for _ in range(args.rounds):
            for key, fn in runs.items():
                t0 = time.perf_counter()
                fn()
                times.setdefault(key, []).append(time.perf_counter() - t0)
    print(f"rtol {args.rtol:g}, {args.rounds} rounds, median ms (ratio to ERK)")
    for name in rigs:
        for how in ("simulate_fmu", "one doStep"):
            base = statistics.median(times[name, "ERK", how])
            cells = [f"{m} {statistics.median(times[name, m, how]) * 1e3:7.2f} "
                     f"({statistics.median(times[name, m, how]) / base:4.2f})" for m in METHODS]
            print(f"{name:6s} {how:13s} " + "  ".join(cells))
    peak = tight.max()
    print("paper rig, |peak on the grid - tight| / peak: " + ", ".join(
        f"{m} {abs(peaks['paper', m].max() - peak) / peak:.1e}" for m in METHODS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
