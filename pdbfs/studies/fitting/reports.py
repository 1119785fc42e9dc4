"""What calibration and design print, plot and write: plain text for the
command line, a matplotlib figure, a CSV of columns. Files are written to
a temporary name and renamed, so a failure never leaves half a file."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from pdbfs import files

SCALE = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm")}


def _fmt(v, unit=""):
    if v is None:
        return "-"
    return f"{v:.6g}{' ' + unit if unit and unit != '1' else ''}"


def calibration_text(cal) -> str:
    """Calibration.report()."""
    lines = [f"rig {cal.rig}: {cal.signal} fitted to {len(cal.t)} samples",
             f"{'parameter':<18} {'value':>14} {'std. error':>12}  unit"]
    for name, v in cal.params.items():
        unit = cal.units.get(name, "")
        if v is None:
            lines.append(f"{name:<18} {'not determined':>14} {'':>12}  {unit}   "
                         f"(held at {cal.held[name]:.6g}: {cal.undetermined[name]})")
        else:
            note = f"   (at its {cal.at_bounds[name][0]} bound)" if name in cal.at_bounds else ""
            lines.append(f"{name:<18} {v:>14.6g} {cal.std[name]:>12.3g}  {unit}{note}")
    k, unit = SCALE.get(cal.unit, (1.0, cal.unit))
    ends = [s.get("optimum") for s in cal.starts]
    n_best = ends.count(0)
    worse, failed = sum(1 for w in ends if w), ends.count(None)
    others = [f"{worse} ended at a worse one" if worse else "",
              f"{failed} failed" if failed else ""]
    lines.append(f"RMS residual {cal.rms_residual * k:.4g} {unit}; {n_best} of {len(cal.starts)} "
                 "start(s) reached this optimum"
                 + "".join(f", {o}" for o in others if o))
    names = list(cal.corr)
    if len(names) > 1:
        lines.append("correlation: " + "; ".join(
            f"{a}~{b} {cal.corr[a][b]:+.2f}" for i, a in enumerate(names) for b in names[i + 1:]))
    return "\n".join(lines)


def design_text(des) -> str:
    """Design.report()."""
    lines = [f"rig {des.rig}: design of {des.signal} "
             + ("(reached)" if des.reachable else "(NOT reached)")]
    for name, v in des.params.items():
        lines.append(f"  {name:<18} {v:>14.6g} {des.units.get(name, '')}"
                     + (f"   (at its {des.at_bounds[name][0]} bound)" if name in des.at_bounds else ""))
    for name, v in des.implied.items():
        lines.append(f"  {name:<18} {v:>14.6g}   (implied)")
    if des.targets:
        for k, t in des.targets.items():
            lines.append(f"  {k:<18} target {t:.6g}, reached {des.features[k]:.6g}")
    if des.rms_error is not None:
        k, unit = SCALE.get(des.unit, (1.0, des.unit))
        lines.append(f"  RMS error {des.rms_error * k:.4g} {unit}, worst deviation "
                     f"{des.worst_deviation * k:.4g} {unit} at t = {des.worst_time * 1e3:.4g} ms")
    if not des.reachable:
        lines.append("  " + des.limit)
    return "\n".join(lines)


def plot_fit(res, path=None, title=None, labels=("trace", "fit")):
    """The curve and the model above, the residuals below (time in ms)."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    k, unit = SCALE.get(res.unit, (1.0, res.unit))
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True,
                                  gridspec_kw={"height_ratios": [3, 1]})
    t = res.t * 1e3
    ax.plot(t, res.y * k, ".", ms=2.5, color="0.45", label=labels[0])
    ax.plot(t, res.fit * k, "-", color="tab:red", lw=1.4, label=labels[1])
    ax.set_ylabel(f"{res.signal} ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=9)
    ax.set_title(title or f"rig {res.rig}", fontsize=10)
    ax2.plot(t, (res.y - res.fit) * k, ".", ms=2, color="tab:blue")
    ax2.axhline(0.0, color="k", lw=0.8)
    ax2.set_ylabel(f"residual ({unit})")
    ax2.set_xlabel("time (ms)")
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig


def save_figure(fig, path):
    """Save a pyplot Figure to ``path`` (its folder made, written whole) and close it."""
    import matplotlib.pyplot as plt
    try:
        return files.save_figure(fig, path, dpi=130)
    finally:
        plt.close(fig)


def write_columns(path, columns: dict):
    """A CSV with one column per entry of ``columns`` (equal lengths)."""
    path = Path(path)
    with files.whole(path) as part, open(part, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(list(columns))
        w.writerows(np.column_stack([np.asarray(v, float) for v in columns.values()]).tolist())
    return path


def plot_design(des, path=None):
    """Curve mode: the target and the designed pulse with their difference;
    feature mode: the designed pulse with the targets marked."""
    if des.y is not None:
        return plot_fit(des, path, title=f"rig {des.rig}: design to a target curve",
                        labels=("target", "designed"))
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    k, unit = SCALE.get(des.unit, (1.0, des.unit))
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ax.plot(des.t * 1e3, des.fit * k, color="tab:red", lw=1.5, label="designed pulse")
    tg = des.targets
    if "peak_pressure" in tg:
        ax.axhline(tg["peak_pressure"] * k, color="k", ls="--", lw=0.9, label="target peak")
    if "time_of_peak" in tg:
        ax.axvline(tg["time_of_peak"] * 1e3, color="k", ls=":", lw=0.9, label="target time of peak")
    if "pulse_duration" in tg:
        base = float(des.fit[0])          # the pulse rises from the start pressure
        level = base + 0.01 * (des.features["peak_pressure"] - base)
        t0 = des.t[int(np.argmax(des.fit > level))]
        ax.plot(np.array([t0, t0 + tg["pulse_duration"]]) * 1e3, [level * k, level * k],
                color="tab:blue", lw=3, alpha=0.6, label="target duration (1 % of the rise)")
    settings = ", ".join(f"{n} = {v:.4g}" for n, v in des.params.items())
    ax.set_title(f"rig {des.rig}: {settings}" + ("" if des.reachable else "  (NOT reached)"),
                 fontsize=9)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel(f"{des.signal} ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path)
    return fig
