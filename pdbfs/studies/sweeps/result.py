"""The result of a sweep: a table with one row per point (its parameters, its
summary, or why it failed), held in memory as columns, or read from the
sweep's folder when the sweep streamed its chunks to disk (then nothing is
held until asked for). Points as objects (``res.points``, ``res[i]``) are
made on demand, for sweeps small enough to look at point by point.
"""
from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.simulation.results.reprs import table

from .exports import SweepExports
from .runner import LIST_KEYS

if TYPE_CHECKING:
    import os

    import pandas as pd

    from .store import Store


@dataclass
class SweepPoint:
    """One point of a sweep: its parameters, and either its summary or the
    reason it failed. ``point["peak_pressure"]`` reads a summary value,
    ``point["hammer.v0"]`` a parameter.

    Attributes
    ----------
    index : int
        The point's number in the sweep, from 0.
    params : dict
        Its swept parameters' values, SI units.
    summary : dict or None
        Its summary (as ``Result.summary``), None if it failed.
    error, error_type : str or None
        Why it failed, and the kind of error (``"SolverError"``); None if it ran.
    result : Result or None
        The point's full Result, when the sweep kept trajectories.
    """

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


class SweepResult(SweepExports):
    """The points of a sweep, in input order: a table with one row per point
    (its parameters, its summary, or why it failed), held in memory, or read
    from the sweep's folder when the sweep streamed its chunks to disk (a
    sweep in memory keeps its columns and makes the pandas frame when first
    asked for it: pandas is imported only then).
    ``res[i]`` and iteration give the points as SweepPoints; ``len(res)``
    their number. Made by ``sweep`` (or ``SweepResult.load``).

    Attributes
    ----------
    rig : str
        The rig's name.
    names : list of str
        The swept parameters (and inputs).
    keys : list of str
        The summary keys the table holds.
    frame : pandas.DataFrame
        The table (read from the folder when first asked for).
    store : Store or None
        The folder the sweep was written to, if any.
    elapsed : float
        The sweep's wall time, s.
    workers : int
        The threads or processes it ran on.
    where : str
        Where it ran ("this process", a number of threads or processes, a
        Dask cluster).
    computed : int or None
        The points this run computed (the others were resumed from the folder).

    Examples
    --------
    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5]})
    >>> len(res), res.names, res.n_failed
    (2, ['hammer.v0'], 0)
    >>> point = res[1]
    >>> point["hammer.v0"], f"{point['peak_pressure'] / 1e6:.3g} MPa"
    (3.5, '118 MPa')
    """

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
        """A sweep from the folder it was written to (``sweep(..., out=path)``),
        as far as it got; its table is read when first asked for.

        Parameters
        ----------
        path : str or os.PathLike
            The sweep's folder.

        Returns
        -------
        SweepResult
            The sweep.

        Raises
        ------
        pdbfs.ParameterError
            For a folder that holds no sweep, or whose manifest cannot be read.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> import pdbfs
        >>> from pdbfs.models import paper_rig
        >>> from pdbfs.studies import SweepResult
        >>> folder = Path(tempfile.mkdtemp()) / "v0-sweep"
        >>> _ = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5]}, out=folder)
        >>> [f"{p / 1e6:.3g} MPa" for p in SweepResult.load(folder).values("peak_pressure")]
        ['67.8 MPa', '118 MPa']
        """
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
        """The table as a pandas DataFrame (a copy).

        Returns
        -------
        pandas.DataFrame
            One row per point: its number (``point``), parameters, summary
            keys (SI units; undefined values NaN) and ``error`` ("" where it ran).

        Examples
        --------
        >>> import pdbfs
        >>> from pdbfs.models import paper_rig
        >>> df = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5]}).to_pandas()
        >>> list(df.columns[:3]), len(df)
        (['point', 'hammer.v0', 'peak_pressure'], 2)
        """
        return self.frame.copy()

    def values(self, key: str) -> np.ndarray:
        """A parameter or summary value of every point, in input order.

        Parameters
        ----------
        key : str
            A swept parameter (``"hammer.v0"``) or a summary key
            (``"peak_pressure"``).

        Returns
        -------
        numpy.ndarray
            One float per point, SI units; NaN where a point failed or the
            value is undefined (and for the per-blow lists, such as
            ``impact_times``, which ``rows()`` gives).

        Raises
        ------
        KeyError
            For a key that is neither swept nor in the summary.

        Examples
        --------
        >>> import pdbfs
        >>> from pdbfs.models import paper_rig
        >>> res = pdbfs.sweep(paper_rig(), {"oil.k": [2e8, 3e8]})
        >>> [f"{d * 1e3:.3g} ms" for d in res.values("pulse_duration")]
        ['13 ms', '10.9 ms']
        """
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
        """Every point as a SweepPoint, in input order (made when first asked
        for: a sweep of millions of points is better read as a table).

        Examples
        --------
        >>> import pdbfs
        >>> from pdbfs.models import paper_rig
        >>> res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5]})
        >>> [(p.index, p.params, p.ok) for p in res.points]
        [(0, {'hammer.v0': 2.0}, True), (1, {'hammer.v0': 3.5}, True)]
        """
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
