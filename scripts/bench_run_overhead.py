"""Benchmark: the Python around one run, as ratios against the raw compiled
call of the same run in the same process (CPU time, interleaved rounds,
medians of batches):

* raw: the compiled library's run-and-summary function called through ctypes
  with its arguments made beforehand (the paper rig, 0-20 ms, 2001 output
  points, the explicit method at the default tolerances), its record
  released at once: the C work of every loop below, and nothing else;
* ``rig.simulate().summary()``: the rig's own run;
* ``rig.simulate(params={"hammer.v0": v}).summary()`` with the same ``v``
  each time: the values checked at every run, the start and the choice of
  method="auto" found again;
* the same with a new ``v`` each time (a unit in the last place further):
  a new start, and method="auto" decides again (its estimate reads the
  hammer's speed).

Every run takes the same path; the targets (printed with the ratios, exit
status 1 when one is missed): the rig's own run within ``--own`` (default
1.5) of the raw call, a run with the same parameters within ``--same``
(default 1.15) of the rig's own run, one with new parameters within
``--new`` (default 1.3) of it.

    python scripts/bench_run_overhead.py [--rounds 40] [--batch 20]
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import numpy as np

from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.run.compiled import INFO_N, METHOD_CODES, MSG_LEN, POINT_MSG_LEN, SUMMARY_KEYS

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_campaign import per_call  # noqa: E402


def raw_call(rig):
    """A function making the rig's own run by the compiled library's
    ctypes function alone, its arguments made here, once (the states, the
    parameters and the grid of a run of the rig; its record released)."""
    res = rig.simulate()
    s = res.settings
    assert s["method"] == "erk" and s["backend"] == "c", s
    sim = Simulator.of(rig)
    lib = sim.compiled("erk")
    p, t = res.p, res.t
    x0 = sim.start_vector(p)
    b = lib._block()
    b.p[:] = p
    b.x0[:] = x0
    a = b.addr
    args = (a[0], a[1], t.size, t.ctypes.data, None, float(s["rtol"]), float(s["atol"]),
            METHOD_CODES["erk"], 0.0, int(s["max_num_steps"]), a[2], a[3], MSG_LEN, a[4], a[5],
            a[6], POINT_MSG_LEN * 2, a[7])
    run, release = lib._run_summary, lib._release
    n = INFO_N + len(SUMMARY_KEYS)

    def call():
        if run(*args):
            raise RuntimeError("the raw call failed")
        handle = b.unpack(b.bytes)[-1]
        if handle:
            release(handle)
        return t          # (held by the closure: its address stays valid)
    call()
    assert list(b.unpack(b.bytes)[INFO_N:n]) == res._fast[0], "the raw call is another run"
    return call


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=40)
    ap.add_argument("--batch", type=int, default=20, help="calls per round and loop")
    ap.add_argument("--own", type=float, default=1.5,
                    help="the most the rig's own run may cost, in raw calls")
    ap.add_argument("--same", type=float, default=1.15,
                    help="the most a run with the same params= may cost, in own runs")
    ap.add_argument("--new", type=float, default=1.3,
                    help="the most a run with new params= may cost, in own runs")
    args = ap.parse_args(argv)
    rig = paper_rig()
    v0 = float(rig.simulate().params["hammer.v0"])
    v = [v0]

    def new():
        v[0] = float(np.nextafter(v[0], np.inf))
        return rig.simulate(params={"hammer.v0": v[0]}).summary()

    loops = {"raw": raw_call(rig),
             "own": lambda: rig.simulate().summary(),
             "same": lambda: rig.simulate(params={"hammer.v0": v0}).summary(),
             "new": new}
    for fn in loops.values():          # everything built and warm
        fn()
    times = {k: [] for k in loops}
    names = list(loops)
    for r in range(args.rounds):
        for k in names[r % len(names):] + names[:r % len(names)]:    # each first in turn
            times[k].append(per_call(loops[k], args.batch))
    m = {k: statistics.median(v) for k, v in times.items()}
    print(f"the paper rig, 0-20 ms, 2001 points; {args.rounds} rounds of {args.batch} calls, "
          "CPU time, medians")
    for k, label in (("raw", "the raw compiled call"), ("own", "rig.simulate().summary()"),
                     ("same", "the same params="), ("new", "new params=")):
        print(f"  {label:28s} {1e3 * m[k]:8.3f} ms  {m[k] / m['raw']:5.2f} raw calls")
    checks = [("the rig's own run", m["own"] / m["raw"], args.own, "raw calls"),
              ("the same params=", m["same"] / m["own"], args.same, "own runs"),
              ("new params=", m["new"] / m["own"], args.new, "own runs")]
    failed = False
    for label, ratio, target, unit in checks:
        ok = ratio <= target
        failed |= not ok
        print(f"  {label:28s} {ratio:5.2f} {unit} (target <= {target:g}): "
              f"{'ok' if ok else 'FAIL'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
