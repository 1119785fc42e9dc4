"""The figures of the reproduction, one function each: the paper's Figs. 4-9
with its axes, ranges and legends, and the variant rigs' figures."""
from __future__ import annotations

import numpy as np

from pdbfs.files import save_figure

from .cases import FIGURES, N_PER_MS, OIL_K, SEAL_C, STYLES, V_TABLE1, VELOCITIES


def _axes(title=None, figsize=(6.4, 4.6)):
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=figsize)
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    return fig, ax


def _save(fig, path):
    import matplotlib.pyplot as plt
    fig.tight_layout()
    save_figure(fig, path, dpi=130)
    plt.close(fig)


def _stamp(ax, text="pdbfs, Table 1; linear oil column (k2 in N/m), D = 1.595e6"):
    ax.text(0.01, 0.99, text, transform=ax.transAxes, ha="left", va="top", fontsize=7,
            color="0.4")


def _row(rep, figure, curve, summary):
    rep.table.append({"figure": figure, "curve": curve,
                      "peak_pressure_MPa": summary["peak_pressure"] / 1e6,
                      "time_of_peak_ms": summary["time_of_peak"] * 1e3,
                      "pulse_duration_ms": summary["pulse_duration"] * 1e3,
                      "peak_contact_force_MN": summary["peak_contact_force"] / 1e6,
                      "max_piston_displacement_mm": summary["max_piston_displacement"] * 1e3})


def _window(res, t_max):
    k = int(np.searchsorted(res.t, t_max, side="right"))
    return slice(0, k)


def _pressure_study(ctx, rep, path, *, figure, param, values, label, xlim, ylim, title,
                    caption):
    sw = ctx.study(param, values)
    fig, ax = _axes(title)
    for pt, v, st in zip(sw, values, STYLES):
        if not pt.ok:
            raise RuntimeError(f"{figure}: {param} = {v} failed: {pt.error}")
        w = _window(pt.result, xlim[1] * 1e-3)
        ax.plot(pt.result.t[w] * 1e3, pt.result["oil.pressure"][w] / 1e6, label=label(v), **st)
        _row(rep, figure, label(v), pt.summary)
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_yticks(np.arange(ylim[0], ylim[1] + 1, 50))
    ax.set_xticks(np.arange(xlim[0], xlim[1] + 0.1, 2 if xlim[1] <= 14 else 5))
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Pressure (MPa)")
    ax.legend(loc="upper right", fontsize=9)
    _stamp(ax, caption)
    _save(fig, path)
    return sw


# ------------------------------------------------------------------ Fig. 4
def fig4(ctx, rep, path):
    """Contact force hammer -> piston at 2.73 m/s, 0-14 ms, impulses shaded."""
    import matplotlib.pyplot as plt
    from pdbfs.simulation.results.impulse import impulse_ratio, integral, restitution_from_force
    from pdbfs.simulation.results.summary import restitution
    # impulses are integrated on the output grid: always the fine one (1 run)
    res = ctx.rig.simulate(0.02, n_out=int(0.02e3 * N_PER_MS) + 1)
    t, f = res.t, res["contact.fc"]
    s = res.summary()
    t_pk, f_pk = res.peak("contact.fc")
    # first contact: the run of positive force from t = 0, split at its own peak
    sep = res.crossings("contact.d")
    t_sep1 = float(sep[0])
    e_first = restitution(res, "contact.fc")          # no striker role: first contact
    # the whole blow (every contact hump), split at the overall force peak
    tt, ff = _with_point(t, f, t_pk, f_pk)
    before, after = integral(tt, ff, tt[0], t_pk), integral(tt, ff, t_pk, tt[-1])
    e_blow_peak = impulse_ratio(tt, ff, t_pk)
    # the whole blow, split where the hammer stops: what summary() reports
    t_stop = float(res.crossings("hammer.v")[0])
    v_end = res["hammer.v"][-1]
    e_blow_stop = s["restitution_coefficient"]
    # and the first contact split at its maximum indentation (Poisson)
    t_dmax = _local_max_time(res, "contact.d", 0.0, t_sep1)
    e_first_dmax = restitution_from_force(t, f, t_split=t_dmax)
    rep.notes.update(e_first_peak=e_first, e_blow_peak=e_blow_peak, e_blow_stop=e_blow_stop,
                     e_first_dmax=e_first_dmax, t_force_peak=t_pk, t_hammer_stop=t_stop,
                     force_peak=f_pk, hammer_rebound=-v_end / V_TABLE1,
                     contacts=[float(x) for x in sep], impulse_total=integral(t, f, t[0], t[-1]))

    fig, (ax, axz) = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [2.2, 1]})
    ms, MN = tt * 1e3, ff / 1e6
    ax.fill_between(ms, 0, MN, where=tt <= t_pk, color="tab:blue", alpha=0.25,
                    label=f"indentation impulse $P_i$ = {before:.0f} N s")
    ax.fill_between(ms, 0, MN, where=tt >= t_pk, color="tab:orange", alpha=0.3,
                    label=f"restitution impulse $P_f$ = {after:.0f} N s")
    ax.plot(ms, MN, "k", lw=1.4, label="Hammer")
    ax.plot([t_pk * 1e3], [f_pk / 1e6], "kx", ms=9, mew=2)
    ax.annotate("Maximum Force", (t_pk * 1e3, f_pk / 1e6), (t_pk * 1e3 + 1.5, f_pk / 1e6 + 0.9),
                arrowprops=dict(arrowstyle="->"), fontsize=9)
    ax.axvline(t_stop * 1e3, color="0.5", ls=":", lw=1)
    ax.text(t_stop * 1e3 - 0.1, 5.9, "hammer stops", fontsize=8, color="0.35", ha="right")
    ax.set_xlim(0, 14)
    ax.set_ylim(0, 7)
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Force (MN)")
    ax.set_title("Fig. 4: impact force of the hammer on the piston, v = 2.73 m/s", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    txt = (f"Guo & Batzer, $e = P_f/P_i$:\n"
           f"  split at peak force, whole blow: {e_blow_peak:.2f}\n"
           f"  split at peak force, 1st contact: {e_first:.3f}\n"
           f"  split where hammer stops (summary): {e_blow_stop:.3f}\n"
           f"paper: 0.90-0.95")
    ax.text(0.99, 0.74, txt, transform=ax.transAxes, ha="right", va="top", fontsize=8,
            family="monospace", bbox=dict(fc="white", ec="0.7", alpha=0.9))
    _stamp(ax)
    # zoom on the first contact, split at its own peak
    w = tt <= t_sep1 + 1e-4
    k1 = int(np.argmax(np.where(w, ff, -1)))
    axz.fill_between(ms[w], 0, MN[w], where=(tt[w] <= tt[k1]), color="tab:blue", alpha=0.25,
                     label="$P_i$")
    axz.fill_between(ms[w], 0, MN[w], where=(tt[w] >= tt[k1]), color="tab:orange", alpha=0.3,
                     label="$P_f$")
    axz.plot(ms[w], MN[w], "k", lw=1.4)
    axz.plot([ms[k1]], [MN[k1]], "kx", ms=8, mew=2)
    axz.axvline(t_dmax * 1e3, color="0.5", ls=":", lw=1)
    axz.text(t_dmax * 1e3 + 0.02, 0.1, "max.\nindentation", fontsize=7, color="0.35")
    axz.set_xlim(0, t_sep1 * 1e3 + 0.1)
    axz.set_ylim(0, 3)
    axz.set_xlabel("Time (ms)")
    axz.set_title(f"first contact (0-{t_sep1 * 1e3:.2f} ms): $P_f/P_i$ = {e_first:.3f}",
                  fontsize=10)
    axz.grid(True, alpha=0.3)
    axz.legend(fontsize=8, loc="upper right")
    _save(fig, path)
    _row(rep, "Fig. 4/5", "v=2.73 m/s (Table 1)", s)


def _local_max_time(res, name, a, b):
    """Time of the largest value of ``name`` in [a, b], refined on the solution."""
    return res.peak(name, window=(a, b))[0]


def _with_point(t, f, tp, fp):
    k = int(np.searchsorted(t, tp))
    return np.insert(t, k, tp), np.insert(f, k, fp)


# ------------------------------------------------------------------ Fig. 5
def fig5(ctx, rep, path):
    """Fig. 5: the oil pressure at 2.73 m/s, both readings of k2's unit."""
    res = ctx.rig.simulate(0.014, n_out=ctx.n_out(0.014))
    alt = ctx.rig.simulate(0.014, n_out=ctx.n_out(0.014), params={"oil.n": 1.5})
    fig, ax = _axes("Fig. 5: pressure exerted on the breech assembly, v = 2.73 m/s",
                    figsize=(7.4, 5.0))
    ax.plot(res.t * 1e3, res["oil.pressure"] / 1e6, "k", lw=1.6, label="Simulation")
    ax.plot(alt.t * 1e3, alt["oil.pressure"] / 1e6, color="0.55", ls="--", lw=1.1,
            label="Simulation, k2 read as N/m$^{1.5}$")
    ax.set_xlim(0, 14)
    ax.set_ylim(0, 100)
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Pressure (MPa)")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, fontsize=8, frameon=False)
    _stamp(ax)
    _save(fig, path)
    rep.notes["hertz_oil_peak"] = float(np.max(alt["oil.pressure"]))
    rep.notes["hertz_oil_p14"] = float(alt["oil.pressure"][-1])


# ------------------------------------------------------------------ Figs. 6-9
def fig6(ctx, rep, path):
    """Fig. 6: the oil pressure for the paper's impact velocities."""
    sw = _pressure_study(
        ctx, rep, path, figure="Fig. 6", param="hammer.v0", values=VELOCITIES,
        label=lambda v: f"v={v:.2f} m/s", xlim=(0, 14), ylim=(0, 200),
        title="Fig. 6: pressure at the oil chamber for different impact velocities",
        caption="pdbfs, Table 1 but v; linear oil column, D = 1.595e6")
    ctx.velocity_sweep = sw


def fig7(ctx, rep, path):
    """Fig. 7: the piston's displacement for the paper's impact velocities."""
    sw = getattr(ctx, "velocity_sweep", None) or ctx.study("hammer.v0", VELOCITIES)
    fig, ax = _axes("Fig. 7: displacement of the loading piston and seal assembly")
    for pt, v, st in zip(sw, VELOCITIES, STYLES):
        w = _window(pt.result, 0.020)
        ax.plot(pt.result.t[w] * 1e3, pt.result["piston.s"][w], label=f"v={v:.2f} m/s", **st)
    ax.set_xlim(0, 20)
    ax.set_xticks(np.arange(0, 21, 5))
    ax.set_ylim(0, 0.025)
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Displacement (m)")
    ax.legend(loc="upper right", fontsize=9)
    _stamp(ax, "pdbfs, Table 1 but v; linear oil column, D = 1.595e6")
    _save(fig, path)
    if not getattr(ctx, "velocity_sweep", None):
        for pt, v in zip(sw, VELOCITIES):
            _row(rep, "Fig. 6/7", f"v={v:.2f} m/s", pt.summary)
    rep.notes["displacement"] = {v: pt.summary["max_piston_displacement"]
                                 for pt, v in zip(sw, VELOCITIES)}


def fig8(ctx, rep, path):
    """Fig. 8: the oil pressure for the paper's seal friction coefficients c2."""
    _pressure_study(
        ctx, rep, path, figure="Fig. 8", param="seal.c", values=SEAL_C,
        label=lambda c: f"c2={c / 10 ** np.floor(np.log10(c)):.3f}E{int(np.log10(c))} Ns/m",
        xlim=(0, 20), ylim=(0, 200), title="Fig. 8: effect of the seal friction c2",
        caption="pdbfs, Table 1 but c2; linear oil column, D = 1.595e6")


def fig9(ctx, rep, path):
    """Fig. 9: the oil pressure for the paper's oil stiffnesses k2."""
    _pressure_study(
        ctx, rep, path, figure="Fig. 9", param="oil.k", values=OIL_K,
        label=lambda k: f"k2={k / 1e8:.3f}E8 N/m", xlim=(0, 20), ylim=(0, 200),
        title="Fig. 9: pressure for different oil stiffnesses k2",
        caption="pdbfs, Table 1 but k2; k2 linear (N/m; the paper prints N/m^1.5)")


# ------------------------------------------------------------------ variants
SPLIT_N = 16


def split_front(ctx, rep, path):
    """How the force front travels through a piston split into 16 masses."""
    import matplotlib.pyplot as plt
    from pdbfs.models import split_piston_rig
    rig = split_piston_rig(SPLIT_N)
    t_end = 0.0015
    res = rig.simulate(t_end, n_out=int(t_end * 1e6) + 1)   # 1 us apart
    chain = rig.force_chain(res)
    level = 1e5
    arrival = [_first_above(res.t, f, level) for _, f in chain]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.6), gridspec_kw={"width_ratios": [3, 2]})
    cmap = plt.get_cmap("viridis")
    for j, (lab, f) in enumerate(chain):
        col = cmap(j / (len(chain) - 1))
        kw = dict(color=col, lw=1.8 if lab in ("contact", "oil") else 0.9)
        ax.plot(res.t * 1e3, f / 1e6, label=lab if lab in ("contact", "oil") or j in (4, 8, 12)
                else None, **kw)
    ax.axhline(level / 1e6, color="0.5", ls=":", lw=1)
    ax.set_xlim(0, t_end * 1e3)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("Time (ms)")
    ax.set_ylabel("Compressive force (MN)")
    ax.set_title(f"Force through a piston split into {SPLIT_N} masses (v = 2.73 m/s)",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, title="section", title_fontsize=8, loc="upper right")
    m, ka = rig.compile().params[rig.compile().p_names.index("piston.m")].value, \
        rig.compile().params[rig.compile().p_names.index("piston.k_axial")].value
    dt_link = np.sqrt(m / ka) / SPLIT_N
    idx = np.arange(len(chain) - 1)   # contact, links: positions along the piston
    arr = np.array(arrival[:-1])
    ax2.plot(idx, arr * 1e6, "o-", color="tab:blue", label=f"front (force > {level / 1e3:.0f} kN)")
    ax2.plot(idx, arr[0] * 1e6 + idx * dt_link * 1e6, "k--", lw=1,
             label=r"$\sqrt{E/\rho}$ bar wave: $\sqrt{m/k_{axial}}/N$ per link")
    ax2.set_xticks(idx[::3], [chain[i][0] for i in idx[::3]], fontsize=8)
    ax2.set_xlabel("section (top: struck face)")
    ax2.set_ylabel(r"arrival time ($\mu$s)")
    ax2.set_title(f"oil column reached at {arrival[-1] * 1e6:.0f} $\\mu$s", fontsize=10)
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8, loc="upper left")
    _save(fig, path)
    slope = np.polyfit(idx[1:], arr[1:], 1)[0]
    rep.notes.update(split_dt_link=slope, split_dt_expected=dt_link,
                     split_speed=1.0 / slope * (1.3564 / SPLIT_N))


def _first_above(t, f, level):
    k = np.flatnonzero(f > level)
    return float(t[k[0]]) if k.size else float("nan")


def damping_laws(ctx, rep, path):
    """The contact with each damping law, side by side."""
    import matplotlib.pyplot as plt
    from pdbfs.components.laws import DAMPING_LAWS
    from pdbfs.models import paper_rig
    laws = [(None, "Table 1 D = 1.595e6")] + [(law, law) for law in DAMPING_LAWS]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.6))
    for (law, lab), st in zip(laws, STYLES):
        rig = ctx.rig if law is None else paper_rig(law=law)
        res = rig.simulate(0.014, n_out=ctx.n_out(0.014))
        prm = res.params
        D = prm["contact.D"] if law is None else DAMPING_LAWS[law](
            prm["contact.k"], prm["contact.e"], prm["contact.v_impact"])
        s = res.summary()
        label = f"{lab}" + ("" if law is None else f" (D = {D:.3g})")
        ax.plot(res.t * 1e3, res["contact.fc"] / 1e6, label=label, **st)
        ax2.plot(res.t * 1e3, res["oil.pressure"] / 1e6, label=label, **st)
        _row(rep, "damping laws", lab, s)
        rep.notes.setdefault("laws", {})[lab] = dict(D=D, **s)
    ax.set_xlim(0, 14)
    ax.set_ylim(0, 7)
    ax.set_ylabel("Contact force (MN)")
    ax2.set_xlim(0, 14)
    ax2.set_ylim(0, 100)
    ax2.set_ylabel("Pressure (MPa)")
    for a, loc in ((ax, "upper right"), (ax2, "lower center")):
        a.set_xlabel("Time (ms)")
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8, loc=loc)
    ax.set_title("Contact force hammer -> piston, v = 2.73 m/s, e = 0.95", fontsize=10)
    ax2.set_title("Pressure at the breech", fontsize=10)
    _save(fig, path)


def drop_blows(ctx, rep, path):
    """The drop-height rig: falling, striking, rebounding, striking again."""
    import matplotlib.pyplot as plt
    from pdbfs.models import drop_rig
    rig = drop_rig()
    t_end = 1.5
    res = rig.simulate(t_end, n_out=int(t_end * (4e3 if ctx.fast else 2e4)) + 1)
    s = res.summary()
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(8, 6.2), sharex=True)
    ax.plot(res.t, -res["hammer.s"] * 1e3, "k", label="hammer")
    ax.plot(res.t, -res["piston.s"] * 1e3, "tab:blue", label="piston face")
    ax.set_ylabel("Height (mm), 0: piston face at rest")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    ax2.plot(res.t, res["oil.pressure"] / 1e6, "k", lw=1)
    for i, (ti, pi) in enumerate(zip(s["impact_times"], s["impact_peak_pressures"])):
        v = res.value_at("hammer.v", ti) - res.value_at("piston.v", ti)
        ax.axvline(ti, color="tab:red", ls=":", lw=0.8)
        ax2.axvline(ti, color="tab:red", ls=":", lw=0.8)
        ax2.annotate(f"blow {i + 1}\n{pi / 1e6:.1f} MPa\nv = {v:.2f} m/s", (ti, pi / 1e6),
                     (ti + 0.03, pi / 1e6 - 25), fontsize=8)
    ax2.set_ylim(0, 120)
    ax2.set_xlim(0, t_end)
    ax2.set_xlabel("Time (s)")
    ax2.set_ylabel("Pressure (MPa)")
    ax2.grid(True, alpha=0.3)
    h = res.params["h"]
    ax.set_title(f"Drop rig with gravity: hammer released {h:.2f} m above the piston", fontsize=10)
    _save(fig, path)
    rep.notes["drop"] = dict(times=s["impact_times"], peaks=s["impact_peak_pressures"],
                             v=[res.value_at("hammer.v", ti) for ti in s["impact_times"]])
    for i, (ti, pi) in enumerate(zip(s["impact_times"], s["impact_peak_pressures"])):
        rep.table.append({"figure": "drop rig", "curve": f"blow {i + 1} at {ti:.4f} s",
                          "peak_pressure_MPa": pi / 1e6})


BUILDERS = dict(zip(FIGURES, (fig4, fig5, fig6, fig7, fig8, fig9, split_front, damping_laws,
                               drop_blows)))
