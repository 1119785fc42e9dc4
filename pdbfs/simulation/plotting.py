"""Plots of results (matplotlib, headless)."""
from __future__ import annotations

from pdbfs.files import save_figure

SCALE = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "m/s": (1.0, "m/s")}


#: a curve of more points than twice this is drawn through each bin's lowest
#: and highest sample (a figure 960 pixels wide shows no more)
PLOT_BINS = 4000


def envelope(y, bins: int = PLOT_BINS):
    """Indices of the samples of ``y`` to draw: all of them for a short
    curve; for a long one, the first, the last, and the lowest and highest
    of each of ``bins`` even runs of samples (the peaks are drawn as they
    are; a million-point curve draws in a moment)."""
    import numpy as np
    n = len(y)
    if n <= 2 * bins:
        return slice(None)
    k = -(-n // bins)                       # samples per bin, the last bin padded
    pad = np.concatenate([y, np.full(bins * k - n, y[-1])]).reshape(bins, k)
    base = np.arange(bins) * k
    idx = np.concatenate([[0, n - 1], base + pad.argmin(axis=1), base + pad.argmax(axis=1)])
    return np.unique(np.minimum(idx, n - 1))


def plot_result(res, names=None, path=None, title=None):
    # a Figure without pyplot: pyplot's import (its backends, its state) is most
    # of a one-shot `pdbfs simulate`'s time, and a file needs none of it
    from matplotlib.figure import Figure

    if names is None:
        roles = getattr(res._sim.dae, "signals", {}) or {}
        names = [n for n in (roles.get("pressure"), roles.get("contact_force")) if n]
        names += [n for n in res.names if n.endswith(".s") and n.count(".") == 1
                  and res.units.get(n) == "m" and n in res._sim.dae.x_names]
        if not names:
            names = res._sim.dae.x_names
    else:
        from .settings import name_list
        names = name_list(names, "names", distinct=False)
    by_unit = {}
    for n in names:
        by_unit.setdefault(res.units[n], []).append(n)
    fig = Figure(figsize=(8, 2.6 * len(by_unit)))
    axes = fig.subplots(len(by_unit), 1, sharex=True, squeeze=False)
    t_ms = res.t * 1e3
    for ax, (unit, group) in zip(axes[:, 0], by_unit.items()):
        k, label = SCALE.get(unit, (1.0, unit))
        for n in group:
            keep = envelope(res[n], PLOT_BINS)
            ax.plot(t_ms[keep], res[n][keep] * k, label=n)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    axes[-1, 0].set_xlabel("time [ms]")
    fig.suptitle(title or _title(res), fontsize=10)
    fig.tight_layout()
    if path is not None:
        save_figure(fig, path, dpi=120)
    return fig


def _title(res, most: int = 4) -> str:
    """Which rig, over what time, and the parameters set away from their defaults."""
    import numpy as np
    dae = res._sim.dae
    changed = [f"{n} = {v:.6g} {u}".rstrip() for n, v, d, u in
               zip(dae.p_names, np.asarray(res.p, float), dae.p_default(),
                   [p.unit for p in dae.params]) if not v == d]
    extra = f", {len(changed) - most} more" if len(changed) > most else ""
    head = f"rig {res.rig}: t = 0 .. {res.t[-1]:.6g} s"
    return head + (f"\n{', '.join(changed[:most])}{extra}" if changed else "")
