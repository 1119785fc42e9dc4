"""The result of a sweep: one SweepPoint per parameter point, in input order,
with its summary or the reason it failed; as a table, CSV, DataFrame or an
overlay plot."""
from __future__ import annotations

import csv
import json
from dataclasses import dataclass, field

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.simulation import SUMMARY_UNITS as UNITS


@dataclass
class SweepPoint:
    """One point of a sweep: its parameters, and either its summary or the
    reason it failed. ``result`` is the full pdbfs Result when trajectories
    were requested."""

    index: int
    params: dict
    summary: dict | None = None
    error: str | None = None
    error_type: str | None = None
    result: object = None

    @property
    def ok(self) -> bool:
        return self.error is None

    def __getitem__(self, key):
        if key in self.params:
            return self.params[key]
        if self.summary is None:
            raise KeyError(f"point {self.index} failed ({self.error}); it has no {key!r}")
        return self.summary[key]


@dataclass
class SweepResult:
    """The points of a sweep, in the order of the input."""

    rig: str
    names: list[str]
    points: list[SweepPoint] = field(default_factory=list)
    elapsed: float = 0.0
    workers: int = 1

    def __len__(self):
        return len(self.points)

    def __iter__(self):
        return iter(self.points)

    def __getitem__(self, i) -> SweepPoint:
        return self.points[i]

    @property
    def ok(self) -> list[SweepPoint]:
        return [p for p in self.points if p.ok]

    @property
    def failed(self) -> list[SweepPoint]:
        return [p for p in self.points if not p.ok]

    def values(self, key: str) -> np.ndarray:
        """A parameter or summary value of every point (NaN where a point failed)."""
        out = []
        for p in self.points:
            if key in p.params:
                out.append(p.params[key])
            elif p.summary is not None and key in p.summary:
                v = p.summary[key]
                out.append(v if np.isscalar(v) and v is not None else np.nan)
            elif p.summary is None:
                out.append(np.nan)
            else:
                raise KeyError(f"{key!r} is neither a swept parameter ({', '.join(self.names)}) "
                               f"nor a summary key ({', '.join(p.summary)})")
        return np.asarray(out, dtype=float)

    def summary_keys(self) -> list[str]:
        keys = []
        for p in self.points:
            for k in (p.summary or {}):
                if k not in keys:
                    keys.append(k)
        return keys

    def rows(self) -> list[dict]:
        """One flat dict per point: parameters, summary keys, error."""
        keys = self.summary_keys()
        rows = []
        for p in self.points:
            row = dict(p.params)
            for k in keys:
                v = (p.summary or {}).get(k)
                row[k] = json.dumps(v) if isinstance(v, (list, tuple)) else v
            row["error"] = "" if p.ok else f"{p.error_type}: {p.error}"
            rows.append(row)
        return rows

    def to_csv(self, path):
        """Write one row per point: swept parameters, every summary key (SI
        units in the header), and the error of failed points."""
        keys = self.summary_keys()
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.names + [f"{k} [{UNITS.get(k, '')}]".replace(" []", "")
                                     for k in keys] + ["error"])
            for row in self.rows():
                w.writerow([_cell(row[n]) for n in self.names] + [_cell(row[k]) for k in keys]
                           + [row["error"]])
        return path

    def to_pandas(self):
        """A pandas DataFrame, one row per point (needs pandas installed)."""
        try:
            import pandas as pd
        except ImportError:
            raise PdbfsError("to_pandas() needs pandas: pip install pandas") from None
        return pd.DataFrame(self.rows())

    def plot(self, name=None, path=None, title=None, labels=None, scale=None, ax=None):
        """Overlay ``name`` (by default the rig's pressure) of every point
        against time in ms. Needs trajectories=True."""
        import matplotlib.pyplot as plt
        pts = [p for p in self.points if p.ok]
        if not pts or pts[0].result is None:
            raise PdbfsError("plot() needs the trajectories: run sweep(..., trajectories=True)")
        res0 = pts[0].result
        if name is None:
            name = (getattr(res0._sim.dae, "signals", {}) or {}).get("pressure")
            if name is None:
                raise PdbfsError(f"rig {self.rig} names no pressure signal; pass name=")
        unit = res0.units.get(name, "")
        if scale is None:
            scale, unit = (1e-6, "MPa") if unit == "Pa" else (1.0, unit)
        own = ax is None
        if own:
            fig, ax = plt.subplots(figsize=(7, 4.5))
        varying = [n for n in self.names
                   if len({repr(q.params[n]) for q in self.points}) > 1] or self.names
        for i, p in enumerate(pts):
            lab = labels[i] if labels else ", ".join(f"{k}={_fmt(p.params[k])}" for k in varying)
            ax.plot(p.result.t * 1e3, p.result[name] * scale, label=lab)
        ax.set_xlabel("Time (ms)")
        ax.set_ylabel(f"{name} ({unit})")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        if title:
            ax.set_title(title)
        fig = ax.figure
        if own:
            fig.tight_layout()
        if path is not None:
            fig.savefig(path, dpi=130)
        return fig

    def table(self) -> str:
        """A plain-text table of the points (for the command line)."""
        keys = [k for k in self.summary_keys() if k not in ("impact_times",)]
        head = self.names + [f"{k} [{UNITS.get(k, '')}]" for k in keys]
        lines = ["  ".join(f"{h:>14}" for h in head)]
        for p in self.points:
            cells = [_fmt(p.params[n]) for n in self.names]
            if p.ok:
                cells += [_fmt(p.summary.get(k)) for k in keys]
                lines.append("  ".join(f"{c:>14}" for c in cells))
            else:
                lines.append("  ".join(f"{c:>14}" for c in cells) + f"  FAILED {p.error_type}: {p.error}")
        return "\n".join(lines)


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, np.integer):
        return int(v)
    return v


def _fmt(v):
    if v is None:
        return "-"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    if isinstance(v, (int, float, np.floating)):
        return f"{v:.6g}"
    return str(v)
