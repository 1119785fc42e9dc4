"""Benchmark: the cost of a campaign's blow against a simulate of the same
rig, in one process, interleaved rounds (CPU time, medians):

* ``rig.simulate(t_blow).summary()``: the rig's own run (the baseline);
* the same with new parameters at each call (the striker speed moved by
  1e-9, as a blow of a campaign gets new start temperatures);
* ``campaign(rig, n, period)``: a blow of a campaign (the full simulation
  from the temperatures the blows before left, its summary and end state,
  the pause's closed form, the damage from its peak, the record), its
  history read every 500 blows as by default.

Then one campaign of ``--blows`` blows, timed whole. Fails (exit status 1)
when a blow costs more than ``--limit`` (default 2) simulates.

    python scripts/bench_campaign.py [--rig paper-thermal] [--blows 20000] [--rounds 5]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time

from pdbfs.models import RIGS
from pdbfs.studies.campaign import campaign


def per_call(fn, n: int) -> float:
    """CPU seconds per call of ``fn`` over ``n`` calls."""
    t0 = time.process_time()
    for _ in range(n):
        fn()
    return (time.process_time() - t0) / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rig", default="paper-thermal")
    ap.add_argument("--blows", type=int, default=20000, help="blows of the whole campaign")
    ap.add_argument("--round", type=int, default=2000, help="blows (and simulates) per round")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--period", type=float, default=10.0)
    ap.add_argument("--limit", type=float, default=2.0,
                    help="the most simulates a blow may cost (default 2)")
    args = ap.parse_args(argv)
    rig = RIGS[args.rig]()
    t_blow = float(getattr(rig, "default_t_end", 0.02))
    speed = "hammer.v0" if "hammer.v0" in rig.compile().p_names else None
    bump = [0]

    def moved():
        bump[0] += 1
        return rig.simulate(t_blow, params={speed: 2.73 + 1e-9 * (bump[0] % 1000)}).summary()

    campaign(rig, 20, args.period)                        # everything built and warm
    own, new, blow = [], [], []
    for _ in range(args.rounds):
        own.append(per_call(lambda: rig.simulate(t_blow).summary(), args.round))
        if speed:
            new.append(per_call(moved, args.round))
        t0 = time.process_time()
        campaign(rig, args.round, args.period)
        blow.append((time.process_time() - t0) / args.round)
    m_own, m_blow = statistics.median(own), statistics.median(blow)
    print(f"rig {rig.compile().name}, blows of {t_blow:g} s, one every {args.period:g} s; "
          f"{args.rounds} rounds of {args.round}, CPU time, medians")
    print(f"  simulate (its own run)          {1e3 * m_own:8.3f} ms")
    if new:
        m_new = statistics.median(new)
        print(f"  simulate (new parameters)       {1e3 * m_new:8.3f} ms")
    print(f"  a blow of a campaign            {1e3 * m_blow:8.3f} ms = {m_blow / m_own:.2f} "
          "simulates" + (f" ({m_blow / m_new:.2f} with new parameters)" if new else ""))
    t0, c0 = time.perf_counter(), time.process_time()
    res = campaign(rig, args.blows, args.period)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    o = res.totals
    print(f"  a campaign of {args.blows} blows        {wall:8.2f} s ({cpu:.2f} s CPU; damage "
          f"{o['damage']:.4g}, peak {o['peak_pressure_first']:.4g} -> "
          f"{o['peak_pressure_last']:.4g} Pa)")
    if m_blow > args.limit * m_own:
        print(f"FAIL: a blow costs {m_blow / m_own:.2f} simulates, above {args.limit:g}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
