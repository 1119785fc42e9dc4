"""The figures of the calibration and design tutorials: one calibration (a
synthetic Kistler-like trace with trigger delay, sensor offset and noise),
one design to target features in drop height, one design map.

    python calibration_design.py [--out figures] [--map-n 21]

writes calibration_fit.png, design_features.png, design_map.png, the trace
it fitted (kistler_synthetic.csv, the one `pdbfs example-data` ships) and
the numbers (calibration_design.json) into --out, and prints the reports.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import pdbfs
from pdbfs.models import paper_rig

#: the "measured" rig: what the calibration should find
TRUE = {"oil.k": 3.1e8, "seal.c": 6.0e4, "hammer.v0": 3.2}
SHIFT, OFFSET, NOISE = 1.2e-3, 0.3e6, 0.5e6


def synthetic_trace(path: Path):
    """100 kHz samples of the rig at TRUE, delayed by SHIFT, offset and noisy."""
    t = np.arange(0.0, 0.0215, 1e-5)
    tm = np.round(np.clip(t - SHIFT, 0.0, None), 12)     # no 1e-19 s steps from rounding
    grid = np.unique(np.concatenate([[0.0], tm[tm > 0]]))
    p = paper_rig().simulate(t_out=grid, params=TRUE, rtol=1e-10, atol=1e-12)["oil.pressure"]
    y = np.interp(tm, grid, p) + OFFSET + np.random.default_rng(7).normal(0.0, NOISE, t.size)
    np.savetxt(path, np.column_stack([t, y]), delimiter=",", header="time_s,pressure_Pa",
               comments="")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="figures", help="folder of the figures and numbers")
    ap.add_argument("--map-n", type=int, default=21, help="points per axis of the design map")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    notes = {}

    trace = out / "kistler_synthetic.csv"
    synthetic_trace(trace)
    t0 = time.perf_counter()
    cal = pdbfs.calibrate(paper_rig(), trace, list(TRUE), fit_offset=True)
    notes["calibration_s"] = time.perf_counter() - t0
    cal.plot(out / "calibration_fit.png")
    print(cal.report())
    notes["calibration"] = cal.to_dict()
    notes["truth"] = {**TRUE, "trace.shift": SHIFT, "trace.offset": OFFSET, "noise": NOISE}

    t0 = time.perf_counter()
    des = pdbfs.design(paper_rig(), {"peak_pressure": 150e6, "pulse_duration": 0.009},
                       free=["hammer.h", "oil.k"], bounds={"hammer.h": (0.05, 2.0)})
    notes["design_s"] = time.perf_counter() - t0
    des.plot(out / "design_features.png")
    print(des.report())
    notes["design"] = des.to_dict()

    t0 = time.perf_counter()
    m = pdbfs.design_map(paper_rig(), x=("hammer.h", 0.1, 1.5), y=("oil.k", 1e8, 1e9),
                         n=args.map_n)
    notes["map_s"] = time.perf_counter() - t0
    m.plot(out / "design_map.png")
    print(f"design map: {m.x.size} x {m.y.size} points in {notes['map_s']:.1f} s")
    (out / "calibration_design.json").write_text(json.dumps(notes, indent=2, default=float) + "\n")


if __name__ == "__main__":
    main()
