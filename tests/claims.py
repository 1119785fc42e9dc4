"""The figures README.md and docs/ state, each with the computation that gives it.

A claim is a sentence of a document with placeholders and a function that
returns the values to fill them with; `tests/test_claims.py` computes each and
checks that the filled sentence stands in the document, so a stated figure
cannot drift from the code. Timings are not claims here (they belong to the
benchmarks in scripts/).
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
        c = pdbfs.calibrate(paper_rig(), ROOT / "docs" / "data" / "kistler_synthetic.csv",
                            free=["oil.k", "seal.c", "hammer.v0"], fit_offset=True)
    v, e = c.params, c.std
    return {"k": v["oil.k"] / 1e8, "k_se": e["oil.k"] / 1e5, "c": v["seal.c"] / 1e4,
            "c_se": e["seal.c"] / 1e2, "v0": v["hammer.v0"], "v0_se": e["hammer.v0"] * 1e3,
            "shift": v["trace.shift"] * 1e3, "shift_se": e["trace.shift"] * 1e7,
            "offset": v["trace.offset"] / 1e5, "offset_se": e["trace.offset"] / 1e4,
            "rms": c.rms_residual / 1e6}


CLAIMS = [
    Claim("docs/calibration-design.md",
          "gives hammer.h = {h:.3f} m (an impact speed of {v0:.3f} m/s) and oil.k = {k:.3f}e8 "
          "N/m; simulated afresh the pulse peaks at {peak:.3f} MPa and lasts {duration:.4f} ms",
          one_design),
    Claim("docs/calibration-design.md",
          "| oil.k (N/m) | 3.1e8 | {k:.4f}e8 | {k_se:.1f}e5 | "
          "| seal.c (N s/m) | 6.0e4 | {c:.4f}e4 | {c_se:.1f}e2 | "
          "| hammer.v0 (m/s) | 3.2 | {v0:.5f} | {v0_se:.1f}e-3 | "
          "| trace.shift (s) | 1.2e-3 | {shift:.5f}e-3 | {shift_se:.1f}e-7 | "
          "| trace.offset (Pa) | 3.0e5 | {offset:.3f}e5 | {offset_se:.1f}e4 |", one_calibration),
    Claim("docs/calibration-design.md", "the RMS residual, {rms:.2f} MPa, is the noise",
          one_calibration),
    Claim("docs/hydraulics.md", "Its defaults give {peak:.0f} MPa at {t_peak:.1f} ms, "
          "{duration:.0f} ms above 1 % of the rise", pulse_rig),
    Claim("docs/paper-reproduction.md",
          "The hammer first kicks the lighter piston (0–{sep1:.2f} ms) and the two separate. The "
          "hammer then catches up at {meet:.2f} ms, and the piston rattles between the hammer "
          "and the oil until {end:.1f} ms. A last short contact follows at {last0:.1f}–{last1:.1f} "
          "ms.", paper_contacts),
    Claim("docs/paper-reproduction.md",
          "The largest force is {force:.2f} MN at {t_force:.2f} ms", paper_contacts),
    Claim("docs/paper-reproduction.md", "(its largest displacement, {t_stop:.2f} ms;",
          paper_contacts),
    Claim("docs/paper-reproduction.md",
          "Read as linear, the pulse is {peak:.0f} MPa and lasts {duration:.1f} ms", paper_linear),
    Claim("docs/paper-reproduction.md",
          "the pulse at 2.73 m/s reaches only {peak:.1f} MPa, at {t_peak:.1f} ms, and lasts {end:.0f} ms", paper_hertz_oil),
    Claim("docs/paper-reproduction.md", "The largest force is {force:.2f} MN", paper_contact),
    Claim("README.md", "It then equals the hammer's rebound ratio: {e:.2f} at 2.73 m/s",
          paper_linear),
]
