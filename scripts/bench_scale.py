"""Benchmark: how the split-piston rig's costs grow with the number N of
piston masses (2N + 4 states), on this machine, in one run:

* build      split_piston_rig(N).compile(): flattening, structural analysis,
             the CasADi DAE (what the first simulate adds to the others);
* simulate   a further rig.simulate() (0-20 ms, 2001 points, rtol 1e-8,
             atol 1e-10, method "auto"), best of ``--repeat``; with the
             compiled backend too (``--c``, also its build: C generation
             and compilation, once per rig structure);
* FMU        rig.export_fmu(): C generation, compilation, zip (``--fmu``).

With the solver statistics of a run (``Result.stats``; for the compiled
backend its driver's), the steps CVODE took and the cost of one step
(simulate time / steps, in us) are columns too: they tell the growth of
the steps (the chain's fastest mode) from the growth of a step's cost (the
band LU, linear in N).

Each column is also printed as a ratio to N = 1's (the baseline, in the
same process), and fitted as c * N^k over N >= 10: k is the exponent.

    python scripts/bench_scale.py [--n 1,10,100,1000,2000] [--c] [--fmu] [--repeat 2]

``--solvers`` (N = 8, 16, 32, 64 unless ``--n`` is given): the compiled
backend's run of each method ("auto", the default; "erk"; "adams"; "bdf"),
CPU time per run (best of ``--repeat``), steps, right-hand-side and Jacobian
evaluations, the process's peak RSS; Adams and BDF also with dense LU forced
(the same process), and the cost exponent k of each over all N. Exit
status 1 when, at the largest N, band LU takes more than ``--target`` (0.6)
of dense LU's time for Adams or BDF.

    python scripts/bench_scale.py --solvers [--n 8,16,32,64] [--repeat 3] [--target 0.6]

``--against REV`` (N = 64 unless ``--n`` gives one): the default run
(``rig.simulate().summary()``) of this checkout against the same run of
the revision REV (a git worktree of it made for the run and removed after),
each in processes of its own taking turns, CPU time per run (median of
``--repeat`` processes' medians), both peaks against a tight reference
(rtol 1e-11); exit status 1 when this checkout takes more than
``--target`` (0.6) of REV's time or is less accurate than REV at the peak.

    python scripts/bench_scale.py --against 64bd46e [--n 64] [--repeat 5]

Expect the simulate exponent above 1 at a fixed tolerance: the chain's
highest mode (2 c N / L) is excited by the impact and carries more than
the tolerance, so CVODE's steps grow with N (about N^0.6) on top of the
cost of a step (linear in N: sparse or band LU).
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pdbfs.models import split_piston_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled as batch, compiled_build


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def fit(ns, ts):
    ns, ts = np.asarray(ns, float), np.asarray(ts, float)
    keep = (ns >= 10) & np.isfinite(ts) & (ts > 0)
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(ns[keep]), np.log(ts[keep]), 1)[0])


def steps_of(res, rig=None):
    """CVODE's steps in the run of ``res``: from ``res.stats`` where the
    Result has them, else (compiled backend) from its driver, run again with
    the Result's settings; None when neither is at hand."""
    stats = getattr(res, "stats", None)
    if isinstance(stats, dict) and stats.get("steps"):
        return stats["steps"]
    if rig is None:
        return None
    sim, s = Simulator.of(rig), res.settings
    p = sim.param_vector()
    _, st = sim.compiled().run(res.t, sim.start_vector(p), p, s["rtol"], s["atol"], s["method"],
                               s["max_step"], s["max_num_steps"])
    return st.stats["steps"] if st.ok else None


def per_step(row, what, res, rig=None):
    steps = steps_of(res, rig)
    if steps:
        row[f"{what} steps"] = steps
        row[f"{what} us/step"] = row[what] / steps * 1e6


def measure(n, args, tmp):
    row = {}
    rig = split_piston_rig(n)
    row["build"], _ = timed(rig.compile)
    rig.simulate()                          # the integrator's own set-up, once
    runs = [timed(rig.simulate) for _ in range(args.repeat)]
    row["simulate"] = min(t for t, _ in runs)
    per_step(row, "simulate", runs[0][1])
    if args.c:
        row["c build"], _ = timed(lambda: rig.simulate(backend="c", t_end=1e-4, n_out=2))
        runs = [timed(lambda: rig.simulate(backend="c")) for _ in range(args.repeat)]
        row["c simulate"] = min(t for t, _ in runs)
        per_step(row, "c simulate", runs[0][1], rig)
    if args.fmu:
        row["FMU export"], _ = timed(lambda: rig.export_fmu(Path(tmp) / f"split{n}.fmu"))
    return row


#: the driver's code of Newton with dense LU (pdbfs_cvode.h: nls << 4, linsol << 8)
NEWTON_DENSE = 2 << 4 | 1 << 8


def cpu_run(rig, method, repeat):
    """(CPU seconds of one compiled run, best of ``repeat``; its stats)."""
    rig.simulate(backend="c", method=method)
    best, res = float("inf"), None
    for _ in range(repeat):
        t = time.process_time()
        res = rig.simulate(backend="c", method=method)
        best = min(best, time.process_time() - t)
    return best, res.stats


def dense_run(rig, method, repeat):
    """As cpu_run with dense LU forced (checked in the stats)."""
    code = batch.METHOD_CODES[method]
    batch.METHOD_CODES[method] = code | NEWTON_DENSE
    try:
        t, stats = cpu_run(rig, method, repeat)
    finally:
        batch.METHOD_CODES[method] = code
    assert stats["method"].endswith("newton-dense"), stats["method"]
    return t, stats


def solvers(ns, args):
    """The --solvers table; returns the exit status."""
    rows = {}
    print(f"{'N':>4} {'method':>7} {'solver':>18} {'ms/run':>9} {'steps':>7} {'rhs':>7} "
          f"{'jac':>5} {'RSS MB':>7}")
    for n in ns:
        rig = split_piston_rig(n)
        for m in ("auto", "erk", "adams", "bdf", "adams dense", "bdf dense"):
            t, st = (dense_run if m.endswith("dense") else cpu_run)(rig, m.split()[0], args.repeat)
            rows[n, m] = t
            rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            print(f"{n:>4} {m:>7} {st['method']:>18} {t * 1e3:>9.2f} {st['steps']:>7} "
                  f"{st['rhs_evals']:>7} {st['jac_evals']:>5} {rss:>7.0f}", flush=True)
    print("\ncost exponent k of c*N^k over N = " + ", ".join(map(str, ns)))
    methods = ("auto", "erk", "adams", "bdf", "adams dense", "bdf dense")
    print("  " + ", ".join(f"{m} {np.polyfit(np.log(ns), np.log([rows[n, m] for n in ns]), 1)[0]:.2f}"
                           for m in methods))
    big = ns[-1]
    best = min(("erk", "adams", "bdf"), key=lambda m: rows[big, m])
    print(f"N = {big}: default (auto) {rows[big, 'auto'] * 1e3:.1f} ms, best ({best}) "
          f"{rows[big, best] * 1e3:.1f} ms")
    ratios = {m: rows[big, m] / rows[big, f"{m} dense"] for m in ("adams", "bdf")}
    print(f"N = {big}, band LU / dense LU (same process): " +
          ", ".join(f"{m} {r:.2f}" for m, r in ratios.items()) + f" (target <= {args.target})")
    return 0 if max(ratios.values()) <= args.target else 1


#: one process's default runs of split_piston_rig(N): the median CPU time of RUNS, the peak
CHILD = """
import json, sys, time
from pdbfs.models import split_piston_rig
rig = split_piston_rig({n})
rig.simulate().summary()
times = []
for _ in range({runs}):
    t = time.process_time()
    s = rig.simulate().summary()
    times.append(time.process_time() - t)
times.sort()
print(json.dumps({{"cpu": times[len(times) // 2], "peak": s["peak_pressure"]}}))
"""


def _child(root, n, runs):
    env = dict(os.environ, PYTHONPATH=str(root))
    r = subprocess.run([sys.executable, "-c", CHILD.format(n=n, runs=runs)], env=env, cwd=root,
                       capture_output=True, text=True)
    if r.returncode:
        raise SystemExit(f"bench_scale: a run of {root} failed:\n{r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def against(rev, n, args):
    """The --against table; returns the exit status."""
    here = Path(__file__).resolve().parents[1]
    ref = split_piston_rig(n).simulate(rtol=1e-11, method="erk").summary()["peak_pressure"]
    with tempfile.TemporaryDirectory(prefix="pdbfs-against-") as tmp:
        old = Path(tmp) / "rev"
        subprocess.run(["git", "-C", str(here), "worktree", "add", "-q", "--detach", str(old), rev],
                       check=True)
        try:
            _child(old, n, 1)                 # its library built (or found) before timing
            runs = {"this checkout": [], rev: []}
            for _ in range(args.repeat):
                runs["this checkout"].append(_child(here, n, 20))
                runs[rev].append(_child(old, n, 20))
        finally:
            subprocess.run(["git", "-C", str(here), "worktree", "remove", "--force", str(old)],
                           check=False)
    print(f"split_piston_rig({n}).simulate().summary(), default settings; {args.repeat} processes "
          f"each, taking turns; tight peak {ref:.6f} Pa (rtol 1e-11)")
    t, err = {}, {}
    for who, rs in runs.items():
        t[who] = statistics.median(r["cpu"] for r in rs)
        err[who] = abs(rs[-1]["peak"] / ref - 1)
        print(f"  {who:>14}: {t[who] * 1e3:8.2f} ms/run, peak error {err[who]:.1e}")
    ratio = t["this checkout"] / t[rev]
    ok = ratio <= args.target and err["this checkout"] <= max(2 * err[rev], 1e-9)
    print(f"N = {n}: this checkout / {rev}: {ratio:.2f} (target <= {args.target}) at peak error "
          f"{err['this checkout']:.1e} against {err[rev]:.1e}: {'ok' if ok else 'MISSED'}")
    return 0 if ok else 1


def shown(column, v):
    if column.endswith("steps"):
        return f"{v:d}"
    return f"{v:.3g}" if column.endswith("step") else f"{v:.3g} s"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", default="1,10,100,1000,2000", help="numbers of piston masses")
    ap.add_argument("--c", action="store_true", help="also the compiled backend")
    ap.add_argument("--fmu", action="store_true", help="also FMU export")
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--solvers", action="store_true",
                    help="each method's compiled run, band against dense LU")
    ap.add_argument("--target", type=float, default=0.6,
                    help="--solvers: the largest band/dense time ratio passed; --against: the "
                         "largest time ratio to REV's")
    ap.add_argument("--against", metavar="REV",
                    help="the default run at N = 64 against the git revision REV's")
    args = ap.parse_args(argv)
    if args.against:
        return against(args.against, int(args.n) if "--n" in (argv or sys.argv) else 64, args)
    if args.solvers:
        return solvers([int(v) for v in (args.n if "--n" in (argv or sys.argv) else
                                         "8,16,32,64").split(",")], args)
    ns = [int(v) for v in args.n.split(",")]
    if args.c:   # a fresh cache of compiled rigs: compilation is measured, not looked up
        fresh = Path(tempfile.mkdtemp(prefix="pdbfs-bench-compiled-"))
        compiled_build.cache_dir = lambda: fresh
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in ns:
            rows[n] = measure(n, args, tmp)
            print(f"N = {n:5d} ({2 * n + 4} states): " + ", ".join(
                f"{k} {shown(k, v)}" for k, v in rows[n].items()), flush=True)
    cols = [c for c in rows[ns[0]] if all(c in rows[n] for n in ns)]
    base = rows[ns[0]]
    print(f"\nratio to N = {ns[0]} (same process), and exponent k of c*N^k over N >= 10")
    print(f"{'N':>6} " + " ".join(f"{c:>12}" for c in cols))
    for n in ns:
        print(f"{n:>6} " + " ".join(f"{rows[n][c] / base[c]:>12.3g}" for c in cols))
    print(f"{'k':>6} " + " ".join(f"{fit(ns, [rows[n][c] for n in ns]):>12.2f}" for c in cols))


if __name__ == "__main__":
    sys.exit(main())
