"""A sweep's table written out: CSV, a plot of its points' trajectories,
and the plain-text table the command line prints (SweepResult's, as
ResultExports is Result's)."""
from __future__ import annotations

import csv
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.files import save_figure, whole
from pdbfs.simulation import SUMMARY_UNITS as UNITS

if TYPE_CHECKING:
    import os

    from matplotlib.axes import Axes
    from matplotlib.figure import Figure


class SweepExports:
    """SweepResult's outputs; they read its ``names``, ``keys``, ``frame``,
    ``points`` and ``store``."""

    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """Write the table as CSV, written whole or not at all: one row per
        point, its swept parameters, every summary key (SI units in the
        header; an undefined value is an empty cell) and its error.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.

        Returns
        -------
        str or os.PathLike
            ``path``.
        """
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
        """Overlay a variable of every point that ran against time in ms
        (a sweep with ``trajectories=True``).

        Parameters
        ----------
        name : str, optional
            The variable (default: the rig's pressure).
        path : str or os.PathLike, optional
            An image file to save the figure to (its format by its suffix).
        title : str, optional
            The axes' title.
        labels : sequence of str, optional
            One legend label per point that ran (default: the parameters
            that vary, with their values).
        scale : float, optional
            A factor for the values (default: 1e-6 for a pressure, shown in
            MPa; else 1).
        ax : matplotlib.axes.Axes, optional
            Axes to draw on (default: a new figure).

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn on.

        Raises
        ------
        pdbfs.PdbfsError
            For a sweep without trajectories, or a rig that names no
            pressure when ``name`` is not given.
        """
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
        """The points as a plain-text table (what the command line prints).

        Parameters
        ----------
        limit : int or None
            The most points shown (None: all); a note says how many more.

        Returns
        -------
        str
            A header (names and summary keys with their units), then one
            line per point (a failed point's error at its end).

        Examples
        --------
        >>> import pdbfs
        >>> from pdbfs.models import paper_rig
        >>> print(pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.5]}).table())
             hammer.v0  peak_pressure [Pa] ...
                     2     6.77524e+07 ...
                   3.5     1.17635e+08 ...
        """
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
