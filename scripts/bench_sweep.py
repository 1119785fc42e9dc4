"""Benchmark: a sweep of the paper rig (summaries only, 0-20 ms, rtol 1e-8,
atol 1e-10; hammer.v0, oil.k and seal.c on a Latin hypercube), points per
second on this machine, in one run:

* pdbfs, backend "c": the C summary driver, one thread per core (and the
  same points cut off at t_end = 4 ms, each followed past it by the driver);
* pdbfs, backend "casadi": CVODES through CasADi and the Python summary,
  one forked process per core;
* the same sweep by hand: the paper's equations in numpy (tests/paper_equations.py)
  with scipy's solve_ivp (DOP853, dense output; peaks and crossings by
  minimize_scalar and brentq on it), one process per core - the baseline.

    python scripts/bench_sweep.py [--points 4000] [--memory 200000]
    python scripts/bench_sweep.py --peers [--points 1000] [--rounds 3]

``--peers``: the sweep of issue 23 (hammer.v0 in [1.5, 5.5] x oil.k in
[1e8, 5e8], peak pressure only), in one process, interleaved rounds (CPU
time of the process, every thread's), every peak against a tight reference
(numbalsoda DOP853 at rtol 1e-13 on a 1 us grid, Hermite-refined; without
numbalsoda the hand-written C at rtol 1e-13): pdbfs.sweep with default
settings, pdbfs.sweep with backend "c", method "adams" (compiled CVODE)
(both taking their column of peaks, ``SweepResult.values``), the paper's
equations written by hand in C (hand_dop853.c, gcc -O2: bench_hand.py) in
an OpenMP loop (same cores) at the loosest tolerance whose median peak
error is no larger than pdbfs's, numbalsoda DOP853 at rtol 1e-8 in a numba
``prange`` loop (same cores), diffrax Dopri8 ``jit(vmap)`` if installed,
scipy solve_ivp DOP853 point by point (on a tenth of the points). The
target (pdbfs.sweep within 1.2x of the hand-written C's loop) is printed
with its measured ratio; the exit status is 1 when it is missed.

``--memory N`` also runs N points (and N/10) to disk and prints the peak
resident memory of both: a sweep streams its chunks, so it does not grow.
"""
from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

import pdbfs
from pdbfs.models import paper_rig
from pdbfs.studies import Grid, Sample

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from paper_equations import TABLE1, make_rhs  # noqa: E402

RANGES = {"hammer.v0": (1.5, 5.5), "oil.k": (1e8, 1e9), "seal.c": (2.5e3, 2.5e5, "log")}
CORES = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()


def by_hand(point):
    """One point written by hand: integrate, then peak, duration, contact peak."""
    v0, k2, c2 = point
    p = dict(TABLE1, v0=v0, k2=k2, c2=c2)
    rhs, forces, _ = make_rhs(**p)
    t = np.linspace(0.0, 0.02, 2001)
    sol = solve_ivp(rhs, (0.0, 0.02), [0, v0, 0, 0, 0, 0], method="DOP853", t_eval=t,
                    dense_output=True, rtol=1e-8, atol=1e-10)
    pres = lambda tt: k2 * max(sol.sol(tt)[2] - sol.sol(tt)[4], 0.0) / p["A"]   # noqa: E731
    y = k2 * np.clip(sol.y[2] - sol.y[4], 0, None) / p["A"]
    k = int(np.argmax(y))
    r = minimize_scalar(lambda tt: -pres(tt), bounds=(t[max(k - 1, 0)], t[min(k + 1, 2000)]),
                        method="bounded", options={"xatol": 1e-12})
    level = 0.01 * -r.fun
    s = np.sign(y - level)
    cross = [brentq(lambda tt: pres(tt) - level, t[i], t[i + 1]) for i in np.flatnonzero(s[:-1] * s[1:] < 0)]
    fc = np.array([forces(sol.y[:, i])[0] for i in range(t.size)])
    return -r.fun, r.x, float(np.sum(np.diff(cross)[::2])), fc.max()


def rate(f, n):
    t0 = time.perf_counter()
    f()
    return n / (time.perf_counter() - t0)


def rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def peers(n, rounds):
    """The sweep of issue 23 against the hand-written C, numbalsoda, diffrax
    and scipy (see the module doc); the exit status of the target."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import bench_hand
    import bench_peers as bp
    V, K = bench_hand.sweep_points(n)
    T = np.linspace(0.0, 0.02, 2001)
    rig = paper_rig()
    values = {"hammer.v0": V.tolist(), "oil.k": K.tolist()}

    def pdbfs_sweep(**kw):
        # the column of peaks, as numbalsoda's loop returns its array
        return pdbfs.sweep(rig, values, grid=False, progress=False, **kw).values("peak_pressure")
    ref, who = bench_hand.tight_peaks(TABLE1, V, K)
    rtol, err, want = bench_hand.matched_rtol(TABLE1, pdbfs_sweep(), V, K, ref)
    hand = bench_hand.load()
    loop = "OpenMP" if hand.openmp else "pthreads"
    print(f"hand-written C at rtol {rtol:g}: median peak error {err:.1e}, pdbfs's default "
          f"{want:.1e} (reference: {who})")
    runs = {"pdbfs.sweep, default settings": lambda: pdbfs_sweep(),
            "pdbfs.sweep, backend c, method adams": lambda: pdbfs_sweep(backend="c",
                                                                       method="adams"),
            f"hand-written C DOP853 rtol {rtol:g}, {loop} ({CORES} cores)":
                hand.sweep(TABLE1, V, K, rtol=rtol)}
    nb = bp.numbalsoda_sweep(T, TABLE1, V, K)
    if nb is None:
        print("note: numbalsoda not installed (pip install numbalsoda; needs gfortran): skipped")
    else:
        runs[f"numbalsoda DOP853 rtol 1e-8, numba prange ({CORES} cores)"] = nb
    dx = bp.diffrax_sweep(T, TABLE1, V, K)
    if dx is None:
        print("note: diffrax/jax not installed: skipped")
    else:
        runs["diffrax Dopri8 jit(vmap), CPU"] = dx
    m = max(n // 10, 1)
    rhs_pts = list(zip(V[:m], K[:m]))

    def scipy_points():
        out = []
        for v0, k2 in rhs_pts:
            p = dict(TABLE1, v0=v0, k2=k2)
            rhs, _, _ = make_rhs(**p)
            sol = solve_ivp(rhs, (0.0, 0.02), [0, v0, 0, 0, 0, 0], method="DOP853", t_eval=T,
                            rtol=1e-8, atol=1e-10)
            out.append(bp.hermite_peak(T, sol.y, k2, p["A"]))
        return np.array(out)
    runs["scipy solve_ivp DOP853, point by point"] = scipy_points
    points = {k: (m if k.startswith("scipy") else n) for k in runs}
    peaks = {k: f() for k, f in runs.items()}        # warm up (JIT, library), and the answers
    times = {k: [] for k in runs}
    names = list(runs)
    for r in range(rounds):
        for k in names[r % len(names):] + names[:r % len(names)]:
            t0 = time.process_time()
            runs[k]()
            times[k].append((time.process_time() - t0) / points[k])
    base = float(np.median(times[names[0]]))
    w = max(map(len, names))
    print(f"sweep of {n} points, hammer.v0 in [1.5, 5.5] x oil.k in [1e8, 5e8], peak pressure; "
          f"{CORES} cores, {rounds} interleaved rounds, CPU time")
    print(f"{'contender':<{w}} {'us/point':>9} {'vs default':>11} {'median peak error':>18} "
          f"{'worst':>8}")
    for k in names:
        t = float(np.median(times[k]))
        e = np.abs(peaks[k] - ref[:points[k]]) / ref[:points[k]]
        print(f"{k:<{w}} {t * 1e6:9.1f} {t / base:10.2f}x {np.median(e):18.1e} {e.max():8.1e}")
    hand_name = next(k for k in names if k.startswith("hand-written"))
    return bench_hand.check_targets([(f"{n}-point sweep: pdbfs.sweep / hand-written C in an "
                                      f"{loop} loop", base / float(np.median(times[hand_name])),
                                      1.2)])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=None, help="points of the compiled sweep "
                    "(default 4000; with --peers 1000)")
    ap.add_argument("--memory", type=int, default=0, help="also run this many points to disk")
    ap.add_argument("--peers", action="store_true", help="the comparison with numbalsoda, "
                    "diffrax and scipy of issue 23")
    ap.add_argument("--rounds", type=int, default=3, help="interleaved rounds (--peers)")
    args = ap.parse_args(argv)
    if args.peers:
        return peers(args.points or 1000, args.rounds)
    args.points = args.points or 4000
    rig = paper_rig()
    n_c, n_ca, n_sp = args.points, max(args.points // 10, 2 * CORES), max(args.points // 40, 2 * CORES)
    pdbfs.sweep(rig, Sample("lhs", 8, RANGES), backend="c")            # build the library once
    rates = {
        "pdbfs, backend c (C summaries, threads)":
            rate(lambda: pdbfs.sweep(rig, Sample("lhs", n_c, RANGES, seed=1), backend="c"), n_c),
        "pdbfs, backend casadi (processes)":
            rate(lambda: pdbfs.sweep(rig, Sample("lhs", n_ca, RANGES, seed=1), backend="casadi"),
                 n_ca),
    }
    # pulses cut off at t_end: the driver follows each past it (its peak or not)
    cut = rate(lambda: pdbfs.sweep(rig, Sample("lhs", n_c, RANGES, seed=1), backend="c",
                                   t_end=0.004), n_c)
    pts = Sample("lhs", n_sp, RANGES, seed=1).all()
    with ProcessPoolExecutor(CORES) as pool:
        list(pool.map(by_hand, pts[:CORES]))                          # start the workers
        rates["solve_ivp DOP853 by hand (processes)"] = rate(lambda: list(pool.map(by_hand, pts)), n_sp)
    base = rates["solve_ivp DOP853 by hand (processes)"]
    print(f"sweep of the paper rig, summaries, 0-20 ms, rtol 1e-8, {CORES} cores")
    print(f"{'run':<44} {'points/s':>10} {'/ by hand':>10}")
    for name, r in rates.items():
        print(f"{name:<44} {r:>10.0f} {r / base:>9.1f}x")
    full = rates["pdbfs, backend c (C summaries, threads)"]
    print(f"pdbfs, backend c, every pulse cut off at t_end = 4 ms: {cut:.0f} points/s, "
          f"{full / cut:.2f}x the time a point of the 20 ms sweep takes")
    if args.memory:
        with tempfile.TemporaryDirectory() as tmp:
            for n in (args.memory // 10, args.memory):
                t0 = time.perf_counter()
                pdbfs.sweep(rig, Grid({"hammer.v0": np.linspace(1.5, 5.5, n)}), backend="c",
                            out=Path(tmp) / f"s{n}", progress=False)
                print(f"{n} points to disk in {time.perf_counter() - t0:.1f} s; peak resident "
                      f"memory of this process so far {rss_mb():.0f} MB")


if __name__ == "__main__":
    sys.exit(main())
