"""The figures README.md and docs/ state, each with the computation that gives it.

A claim is a sentence of a document with placeholders (``{name:.3f}``) and a
function that computes their values; `tests/test_claims.py` finds the
sentence, reads each stated figure and checks it against the computed value
to the precision the computation supports on any CPU and BLAS: the stated
digits (half a unit of the last one), plus, where the value comes from an
optimizer, its own uncertainty (``tolerance``: a fitted value within its
standard error). Timings are not claims here (they belong to the benchmarks
in scripts/).
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Claim:
    doc: str                        # path from the repository's root
    text: str                       # the sentence, with str.format placeholders
    values: Callable[[], dict]      # computes the placeholders' values
    #: absolute tolerances beyond the stated digits, by placeholder, from the values
    tolerance: Callable[[dict], dict] | None = None


@lru_cache(maxsize=None)
def _summary(rig_name: str, t_end: float, **params) -> dict:
    import pdbfs.models as models
    rig = getattr(models, rig_name)()
    return rig.simulate(t_end, params=params or None).summary()


def _summary_of(rig_name, t_end, params=()):
    return _summary(rig_name, t_end, **dict(params))


def paper_linear():
    s = _summary_of("paper_rig", 0.02)
    return {"peak": s["peak_pressure"] / 1e6, "duration": s["pulse_duration"] * 1e3,
            "e": s["restitution_coefficient"]}


def paper_default():
    s = _summary_of("paper_rig", 0.02)
    return {"peak": s["peak_pressure"] / 1e6, "t_peak": s["time_of_peak"] * 1e3,
            "duration": s["pulse_duration"] * 1e3}


def paper_hertz_oil():
    s = _summary_of("paper_rig", 0.04, (("oil.n", 1.5),))
    return {"peak": s["peak_pressure"] / 1e6, "t_peak": s["time_of_peak"] * 1e3,
            "end": s["pulse_duration"] * 1e3}


def paper_contact():
    s = _summary_of("paper_rig", 0.02)
    return {"force": s["peak_contact_force"] / 1e6}


def pulse_rig():
    s = _summary_of("hydraulic_pulse_rig", 0.03)
    return {"peak": s["peak_pressure"] / 1e6, "t_peak": s["time_of_peak"] * 1e3,
            "duration": s["pulse_duration"] * 1e3}


@lru_cache(maxsize=None)
def paper_contacts():
    """Fig. 4's contact phases at 2.73 m/s: a tight run on a 0.1 us grid (the
    figures are stated to 0.01 ms)."""
    import numpy as np
    from pdbfs.models import paper_rig
    res = paper_rig().simulate(0.02, n_out=200001, backend="casadi", rtol=1e-10, atol=1e-12)
    t, on = res.t * 1e3, res["contact.d"] > 0
    edges = [float(t[i + 1]) for i in np.flatnonzero(np.diff(on.astype(int))) if t[i] > 0]
    k = int(np.argmax(res["contact.fc"]))
    sep1, meet, end, last0, last1 = edges[:5]
    return {"sep1": sep1, "meet": meet, "end": end, "last0": last0, "last1": last1,
            "force": res["contact.fc"][k] / 1e6, "t_force": t[k],
            "t_stop": float(t[int(np.argmax(res["hammer.s"]))])}


@lru_cache(maxsize=None)
def one_design():
    import warnings

    import pdbfs
    from pdbfs.models import paper_rig
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = pdbfs.design(paper_rig(), {"peak_pressure": 150e6, "pulse_duration": 0.009},
                         free=["hammer.h", "oil.k"], bounds={"hammer.h": (0.05, 2)})
    return {"h": d.params["hammer.h"], "v0": d.implied["hammer.v0"], "k": d.params["oil.k"] / 1e8,
            "peak": d.features["peak_pressure"] / 1e6,
            "duration": d.features["pulse_duration"] * 1e3}


@lru_cache(maxsize=None)
def one_calibration():
    import warnings

    import pdbfs
    from pdbfs.models import paper_rig
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # the trace the tutorial fits: the package's example data where it ships it
        trace = pdbfs.example_data("kistler_synthetic.csv") if hasattr(pdbfs, "example_data") \
            else ROOT / "docs" / "data" / "kistler_synthetic.csv"
        c = pdbfs.calibrate(paper_rig(), trace, free=["oil.k", "seal.c", "hammer.v0"],
                            fit_offset=True)
    v, e = c.params, c.std
    return {"k": v["oil.k"] / 1e8, "k_se": e["oil.k"] / 1e5, "c": v["seal.c"] / 1e4,
            "c_se": e["seal.c"] / 1e2, "v0": v["hammer.v0"], "v0_se": e["hammer.v0"] * 1e3,
            "shift": v["trace.shift"] * 1e3, "shift_se": e["trace.shift"] * 1e7,
            "offset": v["trace.offset"] / 1e5, "offset_se": e["trace.offset"] / 1e4,
            "rms": c.rms_residual / 1e6}


def calibration_tolerance(v: dict) -> dict:
    """A fitted value may move by its standard error (another CPU or BLAS moves
    an optimizer's result in its last digits); a standard error by 5 %."""
    tol = {"k": v["k_se"] * 1e5 / 1e8, "c": v["c_se"] * 1e2 / 1e4, "v0": v["v0_se"] * 1e-3,
           "shift": v["shift_se"] * 1e-7 / 1e-3, "offset": v["offset_se"] * 1e4 / 1e5,
           "rms": 1e-3 * v["rms"]}
    tol.update({k: 0.05 * v[k] for k in ("k_se", "c_se", "v0_se", "shift_se", "offset_se")})
    return tol


def design_tolerance(v: dict) -> dict:
    """The design's least squares stop at a relative step of 1e-10 in the
    unknowns; give its results 1e-6."""
    return {k: 1e-6 * abs(x) for k, x in v.items()}


def paper_tight():
    """The default path's peak against a tight reference (CasADi at rtol 1e-12)."""
    default = _summary_of("paper_rig", 0.02)["peak_pressure"]
    import pdbfs.models as models
    tight = models.paper_rig().simulate(0.02, backend="casadi", rtol=1e-12,
                                        atol=1e-14).summary()["peak_pressure"]
    return {"err": abs(default - tight) / tight}


def damped_bar():
    """The bar piston of 64 segments by default, its highest mode damped by zeta_max."""
    import math

    from pdbfs.models import bar_piston_rig
    from pdbfs.models.bar_piston import PISTON_LENGTH, STEEL_E, STEEL_RHO
    n = 64
    rig = bar_piston_rig(n)
    tau = PISTON_LENGTH / (n * math.sqrt(STEEL_E / STEEL_RHO))
    out = {}
    for key, zeta in (("0", 0.0), ("1", 0.01), ("2", 0.1), ("3", 1.0)):
        res = rig.simulate(params={"piston.eta": zeta * STEEL_E * tau})
        out[f"s{key}"] = res.stats["steps"]
        out[f"p{key}"] = res.summary()["peak_pressure"] / 1e6
    return out


CLAIMS = [
    Claim("docs/tutorials/design.md",
          "gives hammer.h = {h:.3f} m (an impact speed of {v0:.3f} m/s) and oil.k = {k:.3f}e8 "
          "N/m; simulated afresh the pulse peaks at {peak:.3f} MPa and lasts {duration:.4f} ms",
          one_design, design_tolerance),
    Claim("docs/tutorials/calibrate.md",
          "| oil.k (N/m) | 3.1e8 | {k:.4f}e8 | {k_se:.1f}e5 | "
          "| seal.c (N s/m) | 6.0e4 | {c:.4f}e4 | {c_se:.1f}e2 | "
          "| hammer.v0 (m/s) | 3.2 | {v0:.5f} | {v0_se:.1f}e-3 | "
          "| trace.shift (s) | 1.2e-3 | {shift:.5f}e-3 | {shift_se:.1f}e-7 | "
          "| trace.offset (Pa) | 3.0e5 | {offset:.3f}e5 | {offset_se:.1f}e4 |", one_calibration,
          calibration_tolerance),
    Claim("docs/tutorials/calibrate.md", "the RMS residual, {rms:.2f} MPa, is the noise",
          one_calibration, calibration_tolerance),
    Claim("docs/tutorials/hydraulic-rig.md", "Its defaults give {peak:.0f} MPa at {t_peak:.1f} ms, "
          "{duration:.0f} ms above 1 % of the rise", pulse_rig),
    Claim("docs/explanation/paper-rig.md",
          "The hammer first kicks the lighter piston (0–{sep1:.2f} ms) and the two separate. The "
          "hammer then catches up at {meet:.2f} ms, and the piston rattles between the hammer "
          "and the oil until {end:.1f} ms. A last short contact follows at {last0:.1f}–{last1:.1f} "
          "ms.", paper_contacts),
    Claim("docs/explanation/paper-rig.md",
          "The largest force is {force:.2f} MN at {t_force:.2f} ms", paper_contacts),
    Claim("docs/explanation/paper-rig.md", "(its largest displacement, {t_stop:.2f} ms;",
          paper_contacts),
    Claim("docs/explanation/paper-rig.md",
          "Read as linear, the pulse is {peak:.0f} MPa and lasts {duration:.1f} ms", paper_linear),
    Claim("docs/explanation/paper-rig.md",
          "the pulse at 2.73 m/s reaches only {peak:.1f} MPa, at {t_peak:.1f} ms, and lasts {end:.0f} ms", paper_hertz_oil),
    Claim("docs/explanation/paper-rig.md", "The largest force is {force:.2f} MN", paper_contact),
    Claim("docs/explanation/paper-rig.md",
          "It then equals the hammer's rebound ratio: {e:.2f} at 2.73 m/s", paper_linear),
    Claim("README.md", "At Table 1's values and 2.73 m/s the pulse peaks at {peak:.1f} MPa at "
          "{t_peak:.2f} ms and lasts {duration:.1f} ms", paper_default),
    Claim("README.md", "| pdbfs default (compiled, explicit RK 8(5,3), rtol 5e-8) | {err:.1e} |",
          paper_tight),
    Claim("docs/benchmarks.md", "| pdbfs default (`simulate().summary()`: compiled, explicit "
          "RK 8(5,3), rtol 5e-8) | {err:.1e} |", paper_tight),
    Claim("docs/explanation/large-rigs.md",
          "| 0 (undamped, the default) | {s0} | {p0:.4f} MPa | | 0.01 | {s1} | {p1:.4f} MPa | "
          "| 0.1 | {s2} | {p2:.4f} MPa | | 1 | {s3} | {p3:.4f} MPa |", damped_bar),
]
