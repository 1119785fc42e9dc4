"""The figure and numbers of the closed-loop tutorial: the closed-loop pulse
rig (a PI controller opening the valve to follow a target pressure pulse)
integrated as one rig, and co-simulated as two FMUs (plant and controller)
connected in an SSP file, by Ecos, libcosim and pdbfs's FMPy master; the
co-simulation error against the monolithic rig at each communication step,
and the order fitted to it.

    python closed_loop.py [--out figures] [--fmi-version 2] [--steps 5e-5,2.5e-5,...]

writes closed_loop.png and closed_loop.json into --out and prints each
engine's errors and order. Ecos and libcosim run where ecospy and
libcosimpy are installed (the tutorial says how), else are left out.
"""
from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import numpy as np

from pdbfs.fmu import cosimulate, export_ssp
from pdbfs.models import LOOP, TARGET, hydraulic_pulse_pid_rig, pulse_controller_rig, pulse_plant_rig

T_END = 0.02
STEPS = (5e-5, 2.5e-5, 1.25e-5, 6.25e-6, 3.125e-6)    # s: communication steps


def ecos(ssp: str, h: float):
    """(t, pressure) of the system run by Ecos at the step h; None without ecospy."""
    import importlib.util
    spec = importlib.util.find_spec("ecospy")
    if spec is None:
        return None
    bins = os.path.join(os.path.dirname(spec.origin), "binaries")
    for exe in ("ecos", "proxyfmu"):                  # the wheel ships them without the run bit
        f = os.path.join(bins, exe)
        if os.path.isfile(f) and not os.access(f, os.X_OK):
            os.chmod(f, os.stat(f).st_mode | 0o111)
    from ecospy import EcosLib, EcosSimulation
    EcosLib.set_log_level("warn")
    sim = EcosSimulation(ssp_path=ssp, step_size=h)
    sim.init()
    t, p = [0.0], [sim.get_real("plant::sensor.y")]
    for _ in range(int(round(T_END / h))):
        sim.step()
        t.append(sim.get_time())
        p.append(sim.get_real("plant::sensor.y"))
    sim.terminate()
    sim.free()
    return np.array(t), np.array(p)


def libcosim(ssp: str, h: float):
    """(t, pressure) of the system run by libcosim at the step h; None without libcosimpy."""
    try:
        from libcosimpy.CosimEnums import CosimVariableType
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
    except ImportError:
        return None
    log_output_level(CosimLogLevel.ERROR)
    ns, n = int(round(h * 1e9)), int(round(T_END / h))
    ex = CosimExecution.from_ssp_file(ssp, step_size=ns)
    idx = {s.name.decode(): s.index for s in ex.slave_infos()}["plant"]
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}["sensor.y"]
    obs = CosimObserver.create_time_series(buffer_size=n + 10)
    ex.add_observer(obs)
    obs.start_time_series(idx, vr, CosimVariableType.REAL)
    ex.simulate_until(n * ns)
    tp, _, vals = obs.time_series_real_samples(idx, vr, from_step=0, sample_count=n + 10)
    return np.array(tp) * 1e-9, np.array(vals)


def master(ssp: str, h: float, interpolate: bool):
    r = cosimulate(ssp, h, outputs=["plant.sensor.y"], interpolate=interpolate, tolerance=1e-10)
    return r.t, r["plant.sensor.y"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="figures", help="folder of the figure and the numbers")
    ap.add_argument("--fmi-version", type=int, default=2, choices=(2, 3))
    ap.add_argument("--steps", default=",".join(f"{h:g}" for h in STEPS),
                    help="communication steps in s, comma-separated (at least two: the order)")
    args = ap.parse_args()
    steps = tuple(sorted((float(h) for h in args.steps.split(",")), reverse=True))
    if len(steps) < 2:
        ap.error("--steps: give at least two communication steps")
    shown = steps[0]                                  # the step the pressure plot shows
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    grid = np.linspace(0.0, T_END, int(round(T_END / steps[-1])) + 1)
    t0 = time.perf_counter()
    mono = hydraulic_pulse_pid_rig().simulate(T_END, t_out=grid, rtol=1e-11, atol=1e-9)
    mono_s = time.perf_counter() - t0
    p_ref = np.asarray(mono["chamber.p"])
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        fmus = {"plant": pulse_plant_rig().export_fmu(Path(tmp) / "plant.fmu", fmi_version=args.fmi_version),
                "controller": pulse_controller_rig().export_fmu(Path(tmp) / "controller.fmu",
                                                                fmi_version=args.fmi_version)}
        ssp = str(export_ssp(Path(tmp) / "pulse_pid.ssp", fmus, LOOP, name="pulse_pid"))
        export_s = time.perf_counter() - t0
        engines = {"Ecos (held)": lambda h: ecos(ssp, h),
                   "libcosim (held)": (lambda h: libcosim(ssp, h)) if args.fmi_version == 2 else None,
                   "FMPy master (held)": lambda h: master(ssp, h, False),
                   "FMPy master (interpolated)": (lambda h: master(ssp, h, True)) if args.fmi_version == 2
                   else None}
        rows, curves = {}, {}
        for name, run in engines.items():
            if run is None:
                continue
            errs, secs = [], []
            for h in steps:
                t0 = time.perf_counter()
                r = run(h)
                if r is None:
                    break
                secs.append(time.perf_counter() - t0)
                t, p = r
                errs.append(float(np.max(np.abs(p - np.interp(t, grid, p_ref)))))
                if h == shown:
                    curves[name] = (t, p)
            if len(errs) == len(steps):
                order = float(np.polyfit(np.log(steps), np.log(errs), 1)[0])
                rows[name] = {"errors_Pa": errs, "seconds": secs, "order": order}
                print(f"{name:28s} order {order:.2f}; max error " + ", ".join(
                    f"{e / 1e3:.3g} kPa" for e in errs) + "; " + ", ".join(f"{s:.2f} s" for s in secs))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax.plot(grid * 1e3, np.interp(grid, *TARGET) / 1e6, "k--", lw=1, label="target")
    ax.plot(grid * 1e3, p_ref / 1e6, lw=2.5, alpha=0.5, label="one rig (monolithic)")
    for name in ("Ecos (held)", "FMPy master (interpolated)"):
        if name in curves:
            ax.plot(curves[name][0] * 1e3, curves[name][1] / 1e6, lw=1,
                    label=f"two FMUs, {name}, step {shown * 1e6:g} us")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("chamber pressure [MPa]")
    ax.set_title("PI-controlled valve: target and achieved pressure")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    zoom = ax.inset_axes([0.63, 0.3, 0.34, 0.32])     # the peak, where the loop lags most
    keep = (grid > 3.8e-3) & (grid < 6.2e-3)
    zoom.plot(grid[keep] * 1e3, p_ref[keep] / 1e6, lw=2.5, alpha=0.5, color="C0")
    zoom.plot(grid[keep] * 1e3, np.interp(grid[keep], *TARGET) / 1e6, "k--", lw=1)
    for k, name in enumerate(("Ecos (held)", "FMPy master (interpolated)")):
        if name in curves:
            t, p = curves[name]
            m = (t > 3.8e-3) & (t < 6.2e-3)
            zoom.plot(t[m] * 1e3, p[m] / 1e6, lw=1, color=f"C{k + 1}")
    zoom.tick_params(labelsize=7)
    zoom.grid(alpha=0.3)
    styles = {"Ecos (held)": "o-", "libcosim (held)": "x--", "FMPy master (held)": "s-",
              "FMPy master (interpolated)": "^-"}
    for name, row in rows.items():
        bx.loglog(np.array(steps) * 1e6, np.array(row["errors_Pa"]) / 1e6, styles.get(name, "o-"),
                  label=f"{name}: order {row['order']:.2f}")
    bx.set_xticks(np.array(steps) * 1e6, [f"{h * 1e6:g}" for h in steps])
    bx.minorticks_off()
    bx.set_xlabel("communication step [us]")
    bx.set_ylabel("max |co-simulated - monolithic| [MPa]")
    bx.set_title("convergence to the monolithic rig")
    bx.grid(alpha=0.3, which="both")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "closed_loop.png", dpi=110)
    plt.close(fig)
    numbers = {"fmi_version": args.fmi_version, "steps_s": list(steps), "engines": rows,
               "monolithic_seconds": mono_s, "export_seconds": export_s,
               "peak_monolithic_Pa": float(p_ref.max())}
    (out / "closed_loop.json").write_text(json.dumps(numbers, indent=1) + "\n")
    print(f"monolithic run {mono_s:.2f} s (compile included); two FMUs and the SSP file {export_s:.1f} s; "
          f"wrote {out / 'closed_loop.png'}")


if __name__ == "__main__":
    main()
