"""Benchmark: one simulation of the paper rig (0-20 ms, 2001 output points)
ending with its peak oil pressure, pdbfs against what a user would write
instead, in one process, interleaved (each round times every contender once,
in turn), median per contender; then each in a loop of its own (warm
caches), median:

* pdbfs default path: ``rig.simulate().summary()`` with no options;
* the same with ``params=`` new at every run, as a user's own loop over
  parameters sets them (hammer.v0 a unit in the last place further each
  time: the same rig, but nothing of the run before can be reused);
* pdbfs ``backend="c", method="adams"`` (compiled CVODE, rtol 1e-8) + summary;
* pdbfs ``backend="casadi"`` (CVODES through CasADi) + summary;
* the paper's three equations written by hand in C with a DOP853 and its
  dense output, the peak located on it (hand_dop853.c, gcc -O2, ctypes:
  bench_hand.py), at the loosest tolerance whose median peak error over 200
  points of the sweep's ranges is no larger than pdbfs's default's;
* numbalsoda DOP853 at rtol 1e-8 (the paper's equations in numba, needs
  gfortran to install), the peak refined on the cubic Hermite interpolant;
* diffrax Dopri8 (JAX, CPU), if installed; else skipped with a note;
* scipy solve_ivp DOP853 on the numpy right-hand side (tests/paper_equations.py).

Last, pdbfs's default path and numbalsoda alone, taking turns (``--pairs``):
the median of the pairs' ratios.

Times are CPU time (this process's), each round a batch of calls. Every
peak is compared with a tight event-located reference (paper_equations.reference,
rtol 1e-12). A missing peer is skipped with a note. The targets (pdbfs's
default run within 1.2x of the hand-written C, at most 0.4x numbalsoda's)
are printed with their measured ratios; the exit status is 1 when one is
missed (or cannot be measured here).

    python scripts/bench_simulate.py [--rounds 30]
"""
import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from paper_equations import TABLE1, make_rhs, pressure, reference  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_hand  # noqa: E402
import bench_peers as peers  # noqa: E402

T = np.linspace(0.0, 0.02, 2001)


def tight_peak(v0=TABLE1["v0"], k2=TABLE1["k2"]):
    X = reference(T, v0=v0, k2=k2)[0]
    p = dict(TABLE1, k2=k2)
    k = int(np.argmax(pressure(X, p)))
    fine = np.linspace(T[k - 1], T[k + 1], 4001)
    Xf = reference(np.r_[np.linspace(0.0, T[k - 1], 20, endpoint=False), fine], v0=v0, k2=k2)[0]
    return float(pressure(Xf[:, 20:], p).max())


HAND = "hand-written C DOP853 (gcc -O2, ctypes)"


def hand_rtol():
    """The hand-written C's tolerance at pdbfs's accuracy (bench_hand.matched_rtol)."""
    import pdbfs
    from pdbfs.models import paper_rig
    V, K = bench_hand.sweep_points(200)
    ref, who = bench_hand.tight_peaks(TABLE1, V, K)
    mine = pdbfs.sweep(paper_rig(), {"hammer.v0": V.tolist(), "oil.k": K.tolist()}, grid=False,
                       progress=False).values("peak_pressure")
    rtol, err, want = bench_hand.matched_rtol(TABLE1, mine, V, K, ref)
    print(f"hand-written C at rtol {rtol:g}: median peak error {err:.1e} over 200 points, pdbfs's "
          f"default {want:.1e} (reference: {who})")
    return rtol


def contenders(rig, rtol_hand):
    import warnings
    rhs, _, _ = make_rhs(**TABLE1)
    y0 = [0, TABLE1["v0"], 0, 0, 0, 0]

    def scipy_dop853():
        s = solve_ivp(rhs, (0, T[-1]), y0, method="DOP853", t_eval=T, rtol=1e-8, atol=1e-10)
        return peaks_hermite(s.y)

    def peaks_hermite(Y):
        return peers.hermite_peak(T, Y, TABLE1["k2"], TABLE1["A"])

    def casadi():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return rig.simulate(backend="casadi").summary()["peak_pressure"]

    v0 = [TABLE1["v0"]]

    def new_params():
        v0[0] = float(np.nextafter(v0[0], np.inf))
        return rig.simulate(params={"hammer.v0": v0[0]}).summary()["peak_pressure"]

    runs = {
        "pdbfs default (simulate + summary)": lambda: rig.simulate().summary()["peak_pressure"],
        "pdbfs default, params= new each run": new_params,
        "pdbfs backend='c', method='adams'": lambda: rig.simulate(
            backend="c", method="adams").summary()["peak_pressure"],
        "pdbfs backend='casadi'": casadi,
        f"{HAND}, rtol {rtol_hand:g}": bench_hand.load().single(TABLE1, rtol=rtol_hand),
    }
    nb = peers.numbalsoda_single(T, TABLE1)
    if nb is None:
        print("note: numbalsoda not installed (pip install numbalsoda; needs gfortran): skipped")
    else:
        runs["numbalsoda DOP853 rtol 1e-8 + Hermite peak"] = nb
    dx = peers.diffrax_single(T, TABLE1)
    if dx is None:
        print("note: diffrax/jax not installed: skipped")
    else:
        runs["diffrax Dopri8 (jit, CPU) + Hermite peak"] = dx
    runs["scipy solve_ivp DOP853 + Hermite peak"] = scipy_dop853
    return runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=30)
    ap.add_argument("--pairs", type=int, default=600, help="pdbfs and numbalsoda taking turns")
    args = ap.parse_args()
    t0 = time.perf_counter()
    from pdbfs.models import paper_rig
    rig = paper_rig()
    rig.simulate().summary()
    print(f"first pdbfs simulate + summary (compile, library from cache or built): "
          f"{time.perf_counter() - t0:.2f} s")
    ref = tight_peak()
    runs = contenders(rig, hand_rtol())
    peaks = {k: f() for k, f in runs.items()}          # warm up (JIT), and the answers
    times = {k: [] for k in runs}
    names = list(runs)
    # a batch per contender and round: some 5 ms of CPU time each
    batch = {}
    for k in names:
        t = time.process_time()
        runs[k]()
        batch[k] = max(1, min(50, int(0.005 / max(time.process_time() - t, 1e-6))))
    for r in range(args.rounds):
        for k in names[r % len(names):] + names[:r % len(names)]:
            t = time.process_time()
            for _ in range(batch[k]):
                runs[k]()
            times[k].append((time.process_time() - t) / batch[k])
    med = {k: float(np.median(v)) for k, v in times.items()}
    # each in a loop of its own too (warm caches): what a loop of one tool sees
    warm = {}
    for k in names:
        n = 3 if med[k] > 0.02 else 60
        ts = []
        for _ in range(n):
            t = time.process_time()
            runs[k]()
            ts.append(time.process_time() - t)
        warm[k] = float(np.median(ts))
    # pdbfs and numbalsoda alone, taking turns (nothing else between them): the
    # median of the pairs' ratios
    nb_name = next((k for k in names if k.startswith("numbalsoda")), None)
    pairs = None
    if nb_name is not None:
        ratios = []
        for _ in range(args.pairs):
            t = time.process_time()
            runs[names[0]]()
            a = time.process_time() - t
            t = time.process_time()
            runs[nb_name]()
            ratios.append((time.process_time() - t) / max(a, 1e-9))
        pairs = float(np.median(ratios))
    base, wbase = med[names[0]], warm[names[0]]
    w = max(map(len, runs))
    print(f"paper rig, 0-20 ms, 2001 points; tight reference peak {ref / 1e6:.6f} MPa; "
          f"{args.rounds} interleaved rounds, then each in a loop of its own")
    print(f"{'contender':<{w}} {'ms/sim':>8} {'vs default':>11} {'own loop':>9} {'vs default':>11} "
          f"{'peak error':>11}")
    for k in names:
        print(f"{k:<{w}} {med[k] * 1e3:8.3f} {med[k] / base:10.2f}x {warm[k] * 1e3:9.3f} "
              f"{warm[k] / wbase:10.2f}x {abs(peaks[k] - ref) / ref:11.1e}")
    if pairs is not None:
        print(f"pdbfs default and numbalsoda taking turns, {args.pairs} pairs: numbalsoda takes "
              f"{pairs:.2f}x pdbfs's time (median of the pairs)")
    hand = next(k for k in names if k.startswith(HAND))
    return bench_hand.check_targets([
        ("paper rig, one run to its summary: pdbfs default / hand-written C", base / med[hand], 1.2),
        ("paper rig, one run to its summary: pdbfs default / numbalsoda DOP853",
         base / med[nb_name] if nb_name else None, 0.4)])


if __name__ == "__main__":
    sys.exit(main())
