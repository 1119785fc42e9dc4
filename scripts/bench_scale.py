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

Expect the simulate exponent above 1 at a fixed tolerance: the chain's
highest mode (2 c N / L) is excited by the impact and carries more than
the tolerance, so CVODE's steps grow with N (about N^0.6) on top of the
cost of a step (linear in N: sparse or band LU).
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from pdbfs.models import split_piston_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled_build


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
    args = ap.parse_args(argv)
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
    main()
