"""The figures and numbers of the hydraulic tutorial: the oil column of the
paper rig with a constant and a pressure-dependent bulk modulus at 2.73 and
5.5 m/s, and the paper-hydraulic and hydraulic-pulse rigs designed to one
target curve.

    python hydraulics.py [--out figures]

writes hydraulic_modulus.png, hydraulic_design.png and the numbers
(hydraulics.json) into --out, and prints the table of the tutorial.
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import pdbfs
from pdbfs.models import hydraulic_pulse_rig, paper_hydraulic_rig, paper_rig

TIGHT = dict(rtol=1e-10, atol=1e-12)
SPEEDS = (2.73, 5.5)
#: oil columns compared: label -> rig builder (K at p = 0 is the paper's k2*L/A in each)
COLUMNS = {
    "constant K, start volume (= paper k2)": lambda: paper_hydraulic_rig(),
    "constant K, volume shrinking with the stroke": lambda: paper_hydraulic_rig(swept=True),
    "K + 7.5 p, volume shrinking (paper-hydraulic-oil)":
        lambda: paper_hydraulic_rig(law="linear", swept=True),
}
#: the target of the design study: a half-sine-squared pulse, 100 MPa, 12 ms
TARGET_PEAK, TARGET_T = 100e6, 0.012
DESIGN_FREE = {"paper-hydraulic": ["hammer.v0", "oil.K"],
               "hydraulic-pulse": ["valve.A", "drain.A", "valve.t_close"]}


def target_curve():
    t = np.arange(0.0, 0.02 + 1e-12, 5e-5)
    y = np.where(t < TARGET_T, TARGET_PEAK * np.sin(np.pi * t / TARGET_T) ** 2, 0.0)
    return t, y


def matched_oil():
    """paper-hydraulic-oil with K (at p = 0) designed so that its peak at
    2.73 m/s is the paper rig's: the same measurement explained by a
    stiffening oil."""
    peak = paper_rig().simulate(0.02, **TIGHT).summary()["peak_pressure"]
    des = pdbfs.design(paper_hydraulic_rig(law="linear", swept=True), {"peak_pressure": peak},
                       free=["oil.K"])
    return float(des.params["oil.K"])


def modulus_study(out: Path, plt):
    rows = []
    K0 = matched_oil()
    COLUMNS[f"K0 + 7.5 p, K0 = {K0 / 1e9:.3f} GPa: the paper's peak at 2.73 m/s"] = \
        lambda: _oil_with_K(K0)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=False)
    for ax, v in zip(axes, SPEEDS):
        ref = paper_rig().simulate(0.02, params={"hammer.v0": v}, **TIGHT)
        for label, make in COLUMNS.items():
            res = make().simulate(0.02, params={"hammer.v0": v}, **TIGHT)
            s = res.summary()
            rows.append({"v0": v, "column": label, **{k: s[k] for k in
                         ("peak_pressure", "time_of_peak", "pulse_duration",
                          "restitution_coefficient")},
                         "max_dev_from_paper": float(np.max(np.abs(res["oil.p"]
                                                                   - ref["oil.pressure"])))})
            ax.plot(res.t * 1e3, res["oil.p"] / 1e6, label=label)
        ax.set_title(f"hammer.v0 = {v} m/s")
        ax.set_xlabel("time [ms]")
        ax.set_ylabel("oil pressure [MPa]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "hydraulic_modulus.png", dpi=120)
    plt.close(fig)
    return rows


def _oil_with_K(K0):
    rig = paper_hydraulic_rig(law="linear", swept=True)
    rig.oil.bind("K", K0)
    return rig


def design_study(out: Path, plt):
    t, y = target_curve()
    found = {}
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(t * 1e3, y / 1e6, "k--", label="target")
    for name, make in (("paper-hydraulic", paper_hydraulic_rig),
                       ("hydraulic-pulse", hydraulic_pulse_rig)):
        t0 = time.perf_counter()
        des = pdbfs.design(make(), (t, y), free=DESIGN_FREE[name])
        wall = time.perf_counter() - t0
        rig = make()
        res = rig.simulate(0.02, params=des.params, **TIGHT)
        sig = rig.compile().signals["pressure"]
        s = res.summary()
        found[name] = {"params": {k: float(v) for k, v in des.params.items()},
                       "rms_error": float(des.rms_error),
                       "worst_deviation": float(des.worst_deviation),
                       "worst_time": float(des.worst_time),
                       "peak_pressure": s["peak_pressure"], "time_of_peak": s["time_of_peak"],
                       "pulse_duration": s["pulse_duration"], "seconds": wall}
        ax.plot(res.t * 1e3, res[sig] / 1e6, label=f"{name} (rms {des.rms_error / 1e6:.2f} MPa)")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("pressure [MPa]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "hydraulic_design.png", dpi=120)
    plt.close(fig)
    return found


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="figures", help="folder of the figures and numbers")
    out = Path(ap.parse_args(argv).out)
    out.mkdir(parents=True, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = paper_hydraulic_rig().simulate(0.02, **TIGHT)
    b = paper_rig().simulate(0.02, **TIGHT)
    repro = float(np.max(np.abs(a["oil.p"] - b["oil.pressure"])) / np.max(b["oil.pressure"]))
    notes = {"reproduction_max_rel_dev": repro, "modulus": modulus_study(out, plt),
             "design": design_study(out, plt)}
    (out / "hydraulics.json").write_text(json.dumps(notes, indent=2, default=float) + "\n")
    print(f"paper-hydraulic vs paper: max |dp| / peak = {repro:.2e}")
    print("| v0 [m/s] | oil column | peak [MPa] | time of peak [ms] | duration [ms] | restitution |")
    print("|---|---|---|---|---|---|")
    for r in notes["modulus"]:
        print(f"| {r['v0']} | {r['column']} | {r['peak_pressure'] / 1e6:.2f} | "
              f"{r['time_of_peak'] * 1e3:.3f} | {r['pulse_duration'] * 1e3:.3f} | "
              f"{r['restitution_coefficient']:.3f} |")
    for name, d in notes["design"].items():
        print(f"{name}: {d}")


if __name__ == "__main__":
    main()
