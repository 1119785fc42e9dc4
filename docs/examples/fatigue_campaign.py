"""The figure and numbers of the fatigue-campaign tutorial: the paper rig
with its heat (paper-thermal), 20,000 blows, one every 10 s, left alone and
held in a band of peak pressure by the operator's rule; the warm-up drift
of the pulse, the hammer speed the rule gives, the oil's temperature, and
each campaign's blows per gun firing and predicted life.

    python fatigue_campaign.py [--out figures] [--blows 20000] [--period 10]

writes fatigue_campaign.png and fatigue_campaign.json into --out and
prints the numbers.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib
import numpy as np

import pdbfs
from pdbfs.fatigue import Breech
from pdbfs.models import paper_thermal_rig
from pdbfs.studies import read_trace
from pdbfs.studies.campaign import HoldPeak, campaign

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="figures")
    ap.add_argument("--blows", type=int, default=20000)
    ap.add_argument("--period", type=float, default=10.0, help="s from one blow to the next")
    args = ap.parse_args(argv)
    out = Path(args.out)
    rig = paper_thermal_rig()
    breech = Breech()
    firing = read_trace(str(pdbfs.example_data("gun_firing.csv")))
    d_firing = breech.damage((firing.t, firing.y))

    t0 = time.perf_counter()
    free = campaign(rig, args.blows, args.period, breech=breech)
    first = free.table["peak_pressure"].iloc[0]
    band = (first * (1 - 1e-3), first * (1 + 1e-3))         # +-0.1 % around the cold blow
    held = campaign(rig, args.blows, args.period, breech=breech, rule=HoldPeak(*band))
    elapsed = time.perf_counter() - t0

    numbers = {"blows": args.blows, "period": args.period, "band": list(band),
               "firing_damage": d_firing, "seconds": elapsed}
    for name, res in (("free", free), ("held", held)):
        o = res.totals
        t = res.table
        numbers[name] = {
            "peak_first": o["peak_pressure_first"], "peak_last": o["peak_pressure_last"],
            "peak_min": o["peak_pressure_min"], "peak_max": o["peak_pressure_max"],
            "oil_first": o["oil_temperature_first"], "oil_last": o["oil_temperature_last"],
            "duration_first": float(t["pulse_duration"].iloc[0]),
            "duration_last": float(t["pulse_duration"].iloc[-1]),
            "v0_last": float(t["hammer.v0"].iloc[-1]),
            "adjustments": int((t["hammer.v0"].diff().fillna(0) != 0).sum()),
            "damage": o["damage"], "life_blows": o["life_blows"],
            "blows_per_firing": d_firing * len(t) / o["damage"],
            "heat_balance": o["heat_balance"], "damage_left_out": o["damage_left_out"]}

    n = free.table["blow"].to_numpy()
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 7.5), sharex=True)
    ax = axes[0]
    ax.plot(n, free.table["peak_pressure"] * 1e-6, lw=1.2, label="left alone")
    ax.plot(n, held.table["peak_pressure"] * 1e-6, lw=1.2, label="held by the rule")
    for level in band:
        ax.axhline(level * 1e-6, color="0.5", lw=0.8, ls="--")
    ax.set_ylabel("peak pressure (MPa)")
    ax.legend(fontsize=8, loc="lower left")
    ax = axes[1]
    ax.plot(n, free.table["hammer.v0"], lw=1.2)
    ax.plot(n, held.table["hammer.v0"], lw=1.2)
    ax.set_ylabel("hammer speed (m/s)")
    ax = axes[2]
    ax.plot(n, free.table["oil_temperature"] - 273.15, lw=1.2)
    ax.plot(n, held.table["oil_temperature"] - 273.15, lw=1.2, ls="--")
    ax.set_ylabel("oil at the blow (°C)")
    ax.set_xlabel("blow")
    ax.set_xscale("log")
    for ax in axes:
        ax.grid(True, alpha=0.3, which="both")
    axes[0].set_title(f"paper-thermal: {args.blows} blows, one every {args.period:g} s")
    fig.tight_layout()
    out.mkdir(parents=True, exist_ok=True)
    fig.savefig(out / "fatigue_campaign.png", dpi=130)
    (out / "fatigue_campaign.json").write_text(json.dumps(numbers, indent=1) + "\n")
    for name in ("free", "held"):
        r = numbers[name]
        print(f"{name}: peak {r['peak_first'] / 1e6:.3f} -> {r['peak_last'] / 1e6:.3f} MPa, "
              f"oil {r['oil_first'] - 273.15:.2f} -> {r['oil_last'] - 273.15:.2f} °C, "
              f"v0 -> {r['v0_last']:.4f} m/s ({r['adjustments']} adjustments), "
              f"{r['blows_per_firing']:.4g} blows per firing, life {r['life_blows']:.4g} blows")
    print(f"{2 * args.blows} blows in {elapsed:.1f} s")


if __name__ == "__main__":
    main()
