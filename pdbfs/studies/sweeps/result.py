"""The result of a sweep: a table with one row per point (its parameters, its
summary, or why it failed), held in memory as columns, or read from the
sweep's folder when the sweep streamed its chunks to disk (then nothing is
held until asked for). Points as objects (``res.points``, ``res[i]``) are
made on demand, for sweeps small enough to look at point by point.
"""
from __future__ import annotations

import csv
import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.files import save_figure, whole
from pdbfs.simulation import SUMMARY_UNITS as UNITS
from pdbfs.simulation.results.reprs import table

from .runner import LIST_KEYS

if TYPE_CHECKING:
    import os

    import pandas as pd
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from .store import Store


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
        """Whether the point ran."""
        return self.error is None

    def __getitem__(self, key):
        if key in self.params:
            return self.params[key]
        if self.summary is None:
            raise KeyError(f"point {self.index} failed ({self.error}); it has no {key!r}")
        return self.summary[key]


class SweepResult:
    """The points of a sweep, in input order. ``frame`` is the table (pandas);
    ``store`` the folder it came from, if any. A sweep in memory keeps its
    table as ``columns`` ({name: values in point order}) and makes the frame
    when first asked for it: pandas is imported only then."""

    def __init__(self, rig: str, names: Sequence[str], keys: Sequence[str],
                 frame: pd.DataFrame | None = None, store: Store | None = None,
                 results: dict | None = None, elapsed: float = 0.0, workers: int = 1,
                 where: str = "this process", columns: dict | None = None):
        self.rig, self.names, self.keys = rig, list(names), list(keys)
        self._frame, self.store, self._columns = frame, store, columns
        self._results = results or {}
        self.elapsed, self.workers, self.where = elapsed, workers, where
        self.computed = None      # points computed by this run (the rest: resumed from disk)
        self._points = None

    @classmethod
    def load(cls, path: str | os.PathLike) -> SweepResult:
        """The sweep written to the folder ``path`` (as far as it got)."""
        from .store import Store
        store = Store.open(path)
        spec = store.spec
        names = list(spec["points"].get("values") or spec["points"].get("ranges", {})) + \
            list(spec["points"].get("dists", {}))
        res = cls(spec.get("rig", "?"), names, [], store=store)
        cols = list(store.head(1).columns)         # not the whole table: its columns
        res.names = [c for c in cols if c in names] or names
        res.keys = [c for c in cols if c not in ("point", "error") and c not in res.names]
        return res

    # -- the table --------------------------------------------------------------
    @property
    def frame(self) -> pd.DataFrame:
        """The table (pandas), made (or read from the store) when first asked
        for; ``to_pandas()`` copies it."""
        if self._frame is None:
            if self._columns is not None:
                import pandas as pd
                self._frame = pd.DataFrame(self._columns)
            else:
                self._frame = self.store.read()
        return self._frame

    def _table(self):
        """The table's columns ({name: values}): as held, else the frame's."""
        if self._columns is not None:
            return self._columns
        return {c: self.frame[c] for c in self.frame.columns}

    def _shown(self) -> tuple[str, list[tuple[str, str]]]:
        rows = [("points", f"{len(self)}"
                 + (f", {self.n_failed} failed" if self.store is None or self._frame is not None
                    else " (in the folder, not read yet)")),
                ("swept", ", ".join(self.names) or "none"),
                ("summary keys", ", ".join(self.keys) or "none")]
        if self.store is not None:
            rows.append(("folder", str(self.store.dir)))
        if self.computed is not None:
            rows.append(("run", f"{self.computed} computed in {self.elapsed:.3g} s on {self.where}"))
        return f"SweepResult of rig {self.rig}", rows

    def __repr__(self) -> str:
        title, rows = self._shown()
        return f"<{title}: " + "; ".join(f"{k} {v}" for k, v in rows) + ">"

    def _repr_html_(self) -> str:
        return table(*self._shown())

    def __len__(self):
        if self._frame is None and self.store is not None:
            return self.store.spec["n_points"]
        return len(next(iter(self._table().values()), ()))

    def to_pandas(self) -> pd.DataFrame:
        """The table as a pandas DataFrame: one row per point (point number,
        parameters, summary keys, error; undefined values are NaN)."""
        return self.frame.copy()

    def values(self, key: str) -> np.ndarray:
        """A parameter or summary value of every point (NaN where a point
        failed or the value is undefined)."""
        if key not in self.names and key not in self.keys:
            raise KeyError(f"{key!r} is neither a swept parameter ({', '.join(self.names)}) "
                           f"nor a summary key ({', '.join(self.keys)})")
        if key in LIST_KEYS:
            return np.full(len(self), np.nan)
        col = self._table()[key]
        return np.array(col, dtype=float) if isinstance(col, np.ndarray) else \
            self.frame[key].to_numpy(dtype=float, na_value=np.nan)

    def summary_keys(self) -> list[str]:
        """The summary keys the table holds."""
        return list(self.keys)

    # -- points -------------------------------------------------------------------
    @property
    def points(self) -> list[SweepPoint]:
        """Every point as a SweepPoint, in input order."""
        if self._points is None:
            self._points = self._make_points(self._table())
        return self._points

    def _make_points(self, table) -> list[SweepPoint]:
        """The rows of ``table`` (a frame, or columns) as SweepPoints, read a
        column at a time (a pandas row per point cost ten times the points'
        own making)."""
        cols = {c: list(v) if isinstance(v, list) else v.tolist() for c, v in table.items()}
        n = len(next(iter(cols.values()), ()))
        index = cols.get("point", range(n))
        errors = cols.get("error", [""] * n)
        params = [cols[name] for name in self.names]
        values = [(k, cols[k]) for k in self.keys]
        out = []
        for i in range(n):
            pt = SweepPoint(index=int(index[i]),
                            params={name: float(col[i]) for name, col in zip(self.names, params)})
            err = errors[i] or ""
            if err:
                typ, _, msg = str(err).partition(": ")
                pt.error_type, pt.error = typ, msg
            else:
                pt.summary = {k: _value(k, col[i]) for k, col in values}
                pt.result = self._results.get(pt.index)
            out.append(pt)
        return out

    def __iter__(self):
        return iter(self.points)

    def __getitem__(self, i) -> SweepPoint:
        return self.points[i]

    @property
    def ok(self) -> list[SweepPoint]:
        """The points that ran."""
        return [p for p in self.points if p.ok]

    @property
    def failed(self) -> list[SweepPoint]:
        """The points that failed, each with its error."""
        return [p for p in self.points if not p.ok]

    @property
    def n_failed(self) -> int:
        """How many points failed (counted without reading the whole table)."""
        if self._frame is None and self.store is not None:    # not read whole for a count
            return self.store.failures()
        return sum(1 for e in self._table()["error"] if e != "") if len(self) else 0

    def rows(self) -> list[dict]:
        """One flat dict per point: parameters, summary keys (lists as JSON), error."""
        out = []
        for p in self.points:
            row = dict(p.params)
            for k in self.keys:
                v = (p.summary or {}).get(k)
                row[k] = json.dumps(v) if isinstance(v, (list, tuple)) else v
            row["error"] = "" if p.ok else f"{p.error_type}: {p.error}"
            out.append(row)
        return out

    # -- output -------------------------------------------------------------------
    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """One row per point: swept parameters, every summary key (SI units in
        the header; an undefined value is an empty cell), and the error."""
        head = self.names + [f"{k} [{UNITS.get(k, '')}]".replace(" []", "") for k in self.keys]
        with whole(path) as part, open(part, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(head + ["error"])
            for row in self.frame[self.names + self.keys + ["error"]].itertuples(index=False):
                w.writerow([_cell(v) for v in row])
        return path

    def plot(self, name: str | None = None, path: str | os.PathLike | None = None,
             title: str | None = None, labels: Sequence[str] | None = None,
             scale: float | None = None, ax: Axes | None = None) -> Figure:
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
            save_figure(fig, path, dpi=130)
        return fig

    def table(self, limit: int | None = 200) -> str:
        """A plain-text table of the points (for the command line; the first
        ``limit`` points)."""
        keys = [k for k in self.keys if k not in ("impact_times",)]
        head = self.names + [f"{k} [{UNITS.get(k, '')}]" for k in keys]
        lines = ["  ".join(f"{h:>14}" for h in head)]
        if limit is None or len(self) <= limit:
            pts = self.points
        else:                    # a sweep on disk: its first chunks only
            pts = self._make_points(self.frame.head(limit) if self._frame is not None or
                                    self.store is None else self.store.head(limit))
        for p in pts:
            cells = [_fmt(p.params[n]) for n in self.names]
            if p.ok:
                cells += [_fmt(p.summary.get(k)) for k in keys]
                lines.append("  ".join(f"{c:>14}" for c in cells))
            else:
                lines.append("  ".join(f"{c:>14}" for c in cells) + f"  FAILED {p.error_type}: {p.error}")
        if len(pts) < len(self):
            lines.append(f"... {len(self) - len(pts)} more points (the whole table: to_csv or "
                         "the sweep's folder)")
        return "\n".join(lines)


def _value(key, v):
    """A table cell as a summary value: None for undefined, lists from JSON."""
    if key in LIST_KEYS:
        return json.loads(v) if isinstance(v, str) and v else None
    if v is None:
        return None
    v = float(v)
    if v != v:                          # NaN: undefined
        return None
    if key == "complete":
        return bool(v)
    return int(v) if key == "impact_count" else v


def _cell(v):
    if v is None or (isinstance(v, (float, np.floating)) and np.isnan(v)):
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
