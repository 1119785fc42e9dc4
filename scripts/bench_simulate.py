"""Benchmark: the paper rig through pdbfs (CasADi + CVODES, and the compiled
CVODE backend) against the same equations written by hand with numpy for
scipy's solve_ivp (RK45, DOP853), in one process, same tolerances, 2001
output points.

    python scripts/bench_simulate.py [--repeat N]

Prints seconds per simulation (median) and ratios against the RK45 baseline.
"""
import argparse
import sys
import time
import timeit
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from paper_equations import TABLE1, make_rhs, pressure  # noqa: E402

RTOL, ATOL = 1e-8, 1e-10
T = np.linspace(0.0, 0.02, 2001)


def median_time(fn, repeat):
    fn()                                   # warm up, untimed
    return float(np.median(timeit.repeat(fn, number=1, repeat=repeat)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=20)
    args = ap.parse_args()

    t0 = time.perf_counter()
    from pdbfs.models import paper_rig
    rig = paper_rig()
    dae = rig.compile()
    build = time.perf_counter() - t0
    t0 = time.perf_counter()
    rig.simulate(t_out=T, rtol=RTOL, atol=ATOL)   # first call builds the integrator
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    rig.simulate(t_out=T, rtol=RTOL, atol=ATOL, backend="c")   # builds or loads the library
    first_c = time.perf_counter() - t0

    rhs, _, _ = make_rhs(**TABLE1)
    y0 = [0, TABLE1["v0"], 0, 0, 0, 0]

    def baseline(method):
        return solve_ivp(rhs, (0, T[-1]), y0, method=method, t_eval=T, rtol=RTOL, atol=ATOL)

    peaks = {"pdbfs": rig.simulate(t_out=T, rtol=RTOL, atol=ATOL)["oil.pressure"].max(),
             "pdbfs-c": rig.simulate(t_out=T, rtol=RTOL, atol=ATOL,
                                     backend="c")["oil.pressure"].max()}
    for m in ("RK45", "DOP853"):
        peaks[m] = pressure(baseline(m).y, TABLE1).max()
    ref = peaks["DOP853"]
    for k, v in peaks.items():
        rel = abs(v - ref) / ref
        print(f"peak pressure {k:<8} {v / 1e6:.6f} MPa (rel. to DOP853: {rel:.1e})")
        assert rel < 1e-6, f"{k} disagrees with the baseline on the peak"

    def scalar_rhs(t, y):   # the same equations with Python floats, no numpy arrays
        x1, v1, x2, v2, x3, v3 = y
        p = TABLE1
        d = x1 - x2
        dn = d ** p["n"] if d > 0 else 0.0
        fc = max(p["k1"] * dn + p["D"] * dn * (v1 - v2), 0.0)
        fo = p["k2"] * (x2 - x3) if x2 > x3 else 0.0
        return [v1, -fc / p["m1"], v2, (fc - fo - p["c2"] * v2) / p["m2"], v3,
                (fo - p["k3"] * x3) / p["m3"]]

    # every run ends with the pressure history in hand
    runs = {
        "pdbfs (CVODES Adams)": lambda: rig.simulate(t_out=T, rtol=RTOL, atol=ATOL)["oil.pressure"],
        "pdbfs states only": lambda: rig.simulate(t_out=T, rtol=RTOL, atol=ATOL),
        "pdbfs (CVODES BDF)": lambda: rig.simulate(t_out=T, rtol=RTOL, atol=ATOL,
                                                   method="bdf")["oil.pressure"],
        "pdbfs (compiled CVODE, backend='c')": lambda: rig.simulate(
            t_out=T, rtol=RTOL, atol=ATOL, backend="c")["oil.pressure"],
        "pdbfs (compiled CVODE BDF, backend='c')": lambda: rig.simulate(
            t_out=T, rtol=RTOL, atol=ATOL, backend="c", method="bdf")["oil.pressure"],
        "solve_ivp RK45": lambda: pressure(baseline("RK45").y, TABLE1),
        "solve_ivp DOP853": lambda: pressure(baseline("DOP853").y, TABLE1),
        "RK45, scalar-float RHS": lambda: pressure(solve_ivp(
            scalar_rhs, (0, T[-1]), y0, t_eval=T, rtol=RTOL, atol=ATOL).y, TABLE1),
    }
    secs = {k: median_time(f, args.repeat) for k, f in runs.items()}
    base = secs["solve_ivp RK45"]
    print(f"\none-off: compile {build * 1e3:.0f} ms, first simulate (integrator build) "
          f"{first * 1e3:.1f} ms, first simulate with backend='c' (library build or load) "
          f"{first_c * 1e3:.0f} ms; {len(dae.x_names)} states")
    print("baseline: RK45 on the numpy right-hand side (tests/paper_equations.py)")
    w = max(map(len, secs))
    print(f"{'run':<{w}} {'s/sim':>10} {'RK45 / this':>12}")
    for k, s in secs.items():
        print(f"{k:<{w}} {s:>10.5f} {base / s:>11.1f}x")


if __name__ == "__main__":
    main()
