#!/usr/bin/env python3
"""Benchmark: what ``method="auto"`` chooses against each method of the
compiled backend ("erk", "adams", "bdf"), on every rig of ``models.RIGS`` at
its default run (0-20 ms), the split piston and the elastic-bar piston at
several piece counts N, and runs where the choice matters (long runs, a
fast mode that decays without oscillating, a stiff mount).

For every case and method: the CPU time of ``rig.simulate(...).summary()``
(the least of interleaved rounds: other work on the machine only adds to it)
and its error against a tight reference (the explicit method at rtol 1e-13):
the relative error of the peak pressure (or, with no pulse, of the peak
contact force; with neither, the largest error of a state on the output grid
over that state's largest magnitude, at least 1e-6).

At equal accuracy: for each method, the loosest rtol of a ladder from which on
(every tighter rtol too) it is at least as accurate as auto's run, and that
run's time (for the method auto chose: auto's own run). auto must be within
FACTOR (1.3) of the best of them, and its peak within the 1e-7 its defaults
promise; the script exits with status 1 otherwise.

    python scripts/bench_auto.py [--rounds 5] [--quick] [--case NAME ...]
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings

import numpy as np

METHODS = ("erk", "adams", "bdf")
FACTOR = 1.3
#: the accuracy the defaults promise (pdbfs.simulation.settings): auto's run within
PROMISE = 1e-7
LADDER = (1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10, 3e-11, 1e-11)
N_OUT = 2001


def cases(quick: bool = False) -> list[tuple]:
    """(label, rig builder, t_end, params) of every case benchmarked; quick: a
    few, each with a clear winner (tests/test_auto_cost.py)."""
    from pdbfs.models import RIGS, bar_piston_rig, paper_rig, split_piston_rig
    if quick:
        return [("split-piston N=16", lambda: split_piston_rig(n=16), 0.02, None),
                ("bar-piston N=8", lambda: bar_piston_rig(n=8), 0.02, None),
                ("paper 0.5 s", paper_rig, 0.5, None),
                ("paper seal.c=1e9", paper_rig, 0.02, {"seal.c": 1e9}),
                ("hydraulic-pulse 2 s", RIGS["hydraulic-pulse"], 2.0, None)]
    out = [(name, build, 0.02, None) for name, build in RIGS.items()]
    out += [(f"split-piston N={n}", lambda n=n: split_piston_rig(n=n), 0.02, None)
            for n in (2, 8, 16, 32)]
    out += [(f"bar-piston N={n}", lambda n=n: bar_piston_rig(n=n), 0.02, None)
            for n in (2, 4, 8, 16, 32)]
    out += [("paper 0.5 s", paper_rig, 0.5, None),
            ("drop 0.5 s", RIGS["drop"], 0.5, None),
            ("drop 1.5 s", RIGS["drop"], 1.5, None),
            ("hydraulic-pulse 2 s", RIGS["hydraulic-pulse"], 2.0, None),
            ("paper seal.c=1e9", paper_rig, 0.02, {"seal.c": 1e9}),
            ("paper mount.k=2.5e12", paper_rig, 0.02, {"mount.k": 2.5e12})]
    return out


def _peak(res) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = res.summary()
    v = s.get("peak_pressure")
    return float(v if v is not None else s.get("peak_contact_force") or 0.0)


class Case:
    """One rig and run: its reference, and each method's runs."""

    def __init__(self, label, build, t_end, params):
        self.label, self.t_end, self.params = label, t_end, params
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.rig = build()
            ref = self.run("erk", 1e-13, atol=1e-15)
        self.ref_x, self.ref_peak = np.asarray(ref._X), _peak(ref)
        # (a state that stays near zero is judged in absolute terms, to 1e-6)
        self.scale = np.maximum(np.abs(self.ref_x).max(axis=1), 1e-6)

    def run(self, method, rtol=None, atol=1e-10):
        return self.rig.simulate(self.t_end, n_out=N_OUT, params=self.params, method=method,
                                 rtol=rtol, atol=atol, backend="c", max_num_steps=10 ** 8)

    def timed(self, method, rtol=None) -> float:
        """CPU seconds of one run and its summary (what a user's run costs)."""
        t = time.process_time()
        _peak(self.run(method, rtol))
        return time.process_time() - t

    def error(self, res) -> float:
        """The peak's relative error; with no peak, the largest error of a
        state on the grid over that state's largest magnitude."""
        if self.ref_peak:
            return abs(_peak(res) - self.ref_peak) / abs(self.ref_peak)
        X = np.asarray(res._X)       # the states on the grid (made from the run if lazy)
        return float(np.max(np.abs(X - self.ref_x).max(axis=1) / self.scale))


def measure(case: Case, rounds: int = 5) -> dict:
    """auto's method and accuracy; each method's time and error at its
    defaults; at auto's accuracy, each method's rtol and time."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        auto = case.run("auto")
        chosen, auto_rtol = auto.settings["method"], auto.settings["rtol"]
        target = case.error(auto)
        default = {m: case.error(case.run(m)) for m in METHODS}
        equal = {}
        for m in METHODS:           # the loosest rtol from which on m is as accurate as auto
            errs = [case.error(case.run(m, r)) for r in LADDER]
            ok = [r for i, r in enumerate(LADDER) if all(e <= target for e in errs[i:])]
            equal[m] = ok[0] if ok else None
        if chosen in METHODS:           # the method auto chose: its own run, at auto's accuracy
            equal[chosen] = auto_rtol
        runs = {"auto": ("auto", None)} | {m: (m, None) for m in METHODS}
        runs |= {f"{m}@": (m, r) for m, r in equal.items() if r is not None}
        times = {k: [] for k in runs}
        once = sum(case.timed(m, r) for m, r in runs.values())     # (warm: plans, libraries)
        keys = list(runs)
        rounds = max(rounds, min(50, int(0.3 / max(once, 1e-6))))  # short runs: more rounds
        for i in range(rounds):                 # interleaved, each round in another order
            for k in keys[i % len(keys):] + keys[:i % len(keys)]:
                times[k].append(case.timed(*runs[k]))
    med = {k: float(np.min(v)) for k, v in times.items()}    # the least: the machine's load aside
    at_equal = {m: med[f"{m}@"] for m, r in equal.items() if r is not None}
    best = min(at_equal, key=at_equal.get)
    return {"chosen": chosen, "accuracy": target, "peak": bool(case.ref_peak), "default": default,
            "equal_rtol": equal,
            "time": med, "at_equal": at_equal, "best": best,
            "ratio": med["auto"] / at_equal[best]}


def verdict(r: dict) -> str:
    """'' when auto is within FACTOR of the best at equal accuracy and its
    peak within the promise; else why not."""
    bad = []
    if r["ratio"] > FACTOR:
        bad.append(f"auto ({r['chosen']}) {r['ratio']:.2f}x the best ({r['best']})")
    if r["peak"] and not r["accuracy"] <= PROMISE:
        bad.append(f"auto's error {r['accuracy']:.1e} > {PROMISE:g}")
    return "; ".join(bad)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="a few cases only")
    ap.add_argument("--case", nargs="*", help="only these cases (labels as printed)")
    args = ap.parse_args(argv)
    head = (f"{'case':24s} {'auto':>5s} {'auto ms':>8s} {'err':>7s} | "
            + " | ".join(f"{m + ' ms':>9s} {'err':>7s}" for m in METHODS)
            + " | at auto's accuracy: " + " ".join(f"{m + ' ms':>9s}" for m in METHODS)
            + f" {'ratio':>6s}")
    print(head)
    failed = []
    for label, build, t_end, params in cases(args.quick):
        if args.case and label not in args.case:
            continue
        r = measure(Case(label, build, t_end, params), args.rounds)
        t = r["time"]
        row = (f"{label:24s} {r['chosen']:>5s} {t['auto'] * 1e3:8.2f} {r['accuracy']:7.1e} | "
               + " | ".join(f"{t[m] * 1e3:9.2f} {r['default'][m]:7.1e}" for m in METHODS)
               + " | " + " ".join(f"{r['at_equal'][m] * 1e3:9.2f}" if m in r["at_equal"]
                                  else f"{'-':>9s}" for m in METHODS)
               + f" {r['ratio']:6.2f}")
        why = verdict(r)
        print(row + (f"  <- {why}" if why else ""), flush=True)
        if why:
            failed.append(f"{label}: {why}")
    print(f"\nms: CPU time of simulate + summary, the least of {args.rounds} or more interleaved rounds; "
          "err: the peak's relative error (with no peak: the largest state error on the grid "
          "over the state's largest magnitude), against the explicit method at rtol 1e-13; "
          "at auto's accuracy: each method at the loosest rtol of "
          f"{LADDER[0]:g}..{LADDER[-1]:g} from which on it is as accurate as auto "
          "('-': never); ratio: auto over the best of those.")
    if failed:
        print(f"auto over {FACTOR}x the best, or less accurate than promised:\n  "
              + "\n  ".join(failed))
        return 1
    print(f"auto within {FACTOR}x of the best method at equal accuracy in every case")
    return 0


if __name__ == "__main__":
    sys.exit(main())
