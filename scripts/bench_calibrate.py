"""Benchmark: a three-parameter calibration of the paper rig (oil.k, seal.c,
hammer.v0 from a noisy 10 ms pressure trace), with exact gradients (CVODES
sensitivities, pdbfs.calibrate) against derivative-free baselines on the
same scaled least-squares problem, in one process:

* least squares with a finite-difference Jacobian (scipy, '2-point');
* Nelder-Mead on the sum of squares (scipy).

and the cost of one calibration against the length of the trace (20 ms,
1 s, 20 s records around the same pulse, written as CSV with units), each in
its own process: wall time and the process's peak RSS, as ratios against
the 20 ms trace.

    python scripts/bench_calibrate.py [--repeat 3] [--horizons-only]
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import least_squares, minimize

import pdbfs
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.studies.fitting.objectives import CurveProblem
from pdbfs.studies.fitting.signal_model import SignalModel
from pdbfs.studies.fitting.traces import check_trace
from pdbfs.studies.fitting.free_parameters import rig_unknowns

TRUE = {"oil.k": 3.1e8, "seal.c": 6.0e4, "hammer.v0": 3.2}
FREE = list(TRUE)


def trace():
    t = np.linspace(0.0, 0.016, 801)
    y = paper_rig().simulate(t_out=t, params=TRUE, rtol=1e-10, atol=1e-12)["oil.pressure"]
    return t, y + np.random.default_rng(1).normal(0.0, 0.5e6, t.size)


def exact(t, y):
    t0 = time.perf_counter()
    cal = pdbfs.calibrate(paper_rig(), (t, y), FREE, starts=1)
    return time.perf_counter() - t0, cal.evaluations, [cal.params[n] for n in FREE]


def problem(t, y):
    sim = Simulator.of(paper_rig())
    unknowns, p0 = rig_unknowns(sim, FREE)
    model = SignalModel(sim, "oil.pressure", FREE, float(t[-1]), p0)
    prob = CurveProblem(model, unknowns, check_trace(t, y), float(np.max(np.abs(y))))
    z0 = np.array([u.z(u.ref) for u in unknowns])
    lo, hi = (np.array(b) for b in zip(*(u.z_bounds for u in unknowns)))
    residual = lambda z: (prob.curve(z, sens=False)[0] - y) / prob.scale   # noqa: E731
    return prob, model, z0, lo, hi, residual


def finite_differences(t, y):
    prob, model, z0, lo, hi, residual = problem(t, y)
    t0 = time.perf_counter()
    r = least_squares(residual, z0, jac="2-point", bounds=(lo, hi), xtol=1e-10, ftol=1e-12)
    return time.perf_counter() - t0, model.evaluations, list(prob.values(r.x).values())


def nelder_mead(t, y):
    prob, model, z0, lo, hi, residual = problem(t, y)
    t0 = time.perf_counter()
    r = minimize(lambda z: 0.5 * float(np.sum(residual(z) ** 2)), z0, method="Nelder-Mead",
                 bounds=list(zip(lo, hi)), options={"xatol": 1e-8, "fatol": 1e-12, "maxfev": 4000})
    return time.perf_counter() - t0, model.evaluations, list(prob.values(r.x).values())


HORIZON_RUN = """
import resource, sys, time
import pdbfs
from pdbfs.models import paper_rig
t0 = time.perf_counter()
cal = pdbfs.calibrate(paper_rig(), sys.argv[1], ["oil.k"], starts=1)
print(time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
      cal.params["oil.k"])
"""


def horizons():
    """One-parameter calibrations to 20 ms, 1 s and 20 s records: time and peak RSS."""
    import subprocess
    import sys
    import tempfile
    from pathlib import Path
    res = paper_rig().simulate(0.02, n_out=401, params={"oil.k": 3.1e8})
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for span in (0.02, 1.0, 20.0):
            t = np.concatenate([res.t, np.linspace(0.02, span, 2001)[1:]]) if span > 0.02 else res.t
            y = np.concatenate([res["oil.pressure"], np.zeros(t.size - res.t.size)])
            path = Path(tmp) / f"trace_{span:g}s.csv"
            np.savetxt(path, np.column_stack([t * 1e3, y / 1e6]), delimiter=",",
                       header="time [ms],oil.pressure [MPa]", comments="")
            out = subprocess.run([sys.executable, "-c", HORIZON_RUN, str(path)], check=True,
                                 capture_output=True, text=True).stdout.split()
            rows.append((span, t.size, float(out[0]), float(out[1]), float(out[2])))
    base_s, base_mb = rows[0][2], rows[0][3]
    print("one-parameter calibration (oil.k) against the trace's length, one process each")
    print(f"{'trace':>8} {'samples':>8} {'s':>8} {'x 20 ms':>8} {'peak RSS MB':>12} {'x 20 ms':>8}"
          f" {'oil.k / true - 1':>17}")
    for span, n, sec, mb, k in rows:
        print(f"{span:>7g}s {n:>8d} {sec:>8.2f} {sec / base_s:>8.2f} {mb:>12.0f} {mb / base_mb:>8.2f}"
              f" {k / 3.1e8 - 1:>+17.1e}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs of each method (median taken)")
    ap.add_argument("--horizons-only", action="store_true", help="only the trace-length table")
    args = ap.parse_args(argv)
    horizons()
    if args.horizons_only:
        return
    t, y = trace()
    exact(t, y)                        # build and cache the integrator once, untimed
    runs = {}
    for name, f in (("pdbfs.calibrate (exact gradients)", exact),
                    ("least squares, finite differences", finite_differences),
                    ("Nelder-Mead", nelder_mead)):
        out = [f(t, y) for _ in range(args.repeat)]
        runs[name] = (float(np.median([o[0] for o in out])), out[0][1], out[0][2])
    base = runs["pdbfs.calibrate (exact gradients)"][0]
    print(f"3-parameter calibration of the paper rig, {len(t)} samples, medians of {args.repeat}")
    print(f"{'method':<36} {'s':>8} {'simulations':>12} {'s / exact':>10}  recovered "
          + ", ".join(FREE))
    for name, (sec, n, vals) in runs.items():
        rel = ", ".join(f"{v / TRUE[k] - 1:+.1e}" for k, v in zip(FREE, vals))
        print(f"{name:<36} {sec:>8.2f} {n:>12d} {sec / base:>10.1f}  {rel}")


if __name__ == "__main__":
    main()
