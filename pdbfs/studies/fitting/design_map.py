"""A design map: peak pressure and pulse duration over two settings of a rig,
computed by one sweep and drawn as contours - the chart a test engineer
pins on the wall to see which settings give which pulse.

    m = pdbfs.design_map(paper_rig(), x=("hammer.v0", 1, 6), y=("oil.k", 1e8, 1e9))
    m.plot("map.png"); m.to_csv("map.csv")
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.components.laws import impact_velocity
import warnings

from pdbfs.errors import ParameterError, PdbfsError, PdbfsWarning, plain
from pdbfs.simulation import Simulator
from pdbfs.simulation.setup.memory import require, table_bytes
from pdbfs.simulation.setup.settings import check_t_end, mapping, real

from .calibration import _rig
from .free_parameters import height_stands_for
from .reports import save_figure, write_columns
from ..sweeps import sweep

if TYPE_CHECKING:
    import os

    from matplotlib.figure import Figure

    from pdbfs.modelling import DAE, Component

MAPPED = ("peak_pressure", "pulse_duration", "time_of_peak")


@dataclass
class DesignMap:
    """Pulse features over a grid of two parameters: what a design can reach.
    Made by ``design_map``.

    Attributes
    ----------
    rig : str
        The rig's name.
    x_name, y_name : str
        The two parameters (``hammer.h`` is a drop height, m).
    x, y : numpy.ndarray
        Their values on the axes, in ``x_unit`` and ``y_unit``.
    values : dict
        Feature (peak_pressure in Pa, pulse_duration and time_of_peak in s)
        -> array of shape (len(y), len(x)); NaN where a point failed or gave
        no complete pulse.
    failed, no_pulse : int
        Points whose run failed, and points without a complete pulse.
    x_unit, y_unit : str
        The axes' units.
    """

    rig: str
    x_name: str
    y_name: str
    x: np.ndarray                  # axis values (as asked: a drop height stays a height)
    y: np.ndarray
    values: dict                   # feature -> (len(y), len(x)) array, NaN where a point failed
    failed: int                    # points whose run failed
    x_unit: str = ""
    y_unit: str = ""
    no_pulse: int = 0              # points that ran but gave no complete pulse (left blank)

    def plot(self, path: str | os.PathLike | None = None) -> Figure:
        """Peak pressure (colour) and pulse duration (contours) over the two
        parameters (log axes where the values are spaced so).

        Parameters
        ----------
        path : str or os.PathLike, optional
            An image file to save the figure to (its format by its suffix).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        import matplotlib
        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt
        X, Y = np.meshgrid(self.x, self.y)
        fig, ax = plt.subplots(figsize=(7.5, 5.5))
        peak = self.values["peak_pressure"] / 1e6
        cf = ax.contourf(X, Y, peak, levels=14, cmap="viridis")
        fig.colorbar(cf, ax=ax, label="peak pressure (MPa)")
        cs = ax.contour(X, Y, self.values["pulse_duration"] * 1e3, levels=10, colors="w",
                        linewidths=1.0)
        ax.clabel(cs, fmt="%.1f ms", fontsize=8)
        from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter
        for vals, axis, scale in ((self.x, ax.xaxis, ax.set_xscale), (self.y, ax.yaxis, ax.set_yscale)):
            if _is_log(vals):   # 1, 2, 5 per decade, as plain numbers: maps span a decade or two
                scale("log")
                axis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
                axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
                axis.set_minor_formatter(NullFormatter())
        ax.set_xlabel(f"{self.x_name} ({self.x_unit})" if self.x_unit else self.x_name)
        ax.set_ylabel(f"{self.y_name} ({self.y_unit})" if self.y_unit else self.y_name)
        ax.set_title(f"rig {self.rig}: peak pressure (colour) and pulse duration (white, ms)",
                     fontsize=10)
        fig.tight_layout()
        if path is not None:
            save_figure(fig, path)
        return fig

    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """Write one row per grid point (both parameters and each feature) as
        CSV, written whole or not at all.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.

        Returns
        -------
        str or os.PathLike
            ``path``.
        """
        X, Y = np.meshgrid(self.x, self.y)
        cols = {self.x_name: X.ravel(), self.y_name: Y.ravel()}
        cols.update({k: v.ravel() for k, v in self.values.items()})
        return write_columns(path, cols)


def _is_log(v) -> bool:
    return len(v) > 2 and v[0] > 0 and np.allclose(np.diff(np.log(v)), np.log(v[1] / v[0]))


def axis(spec, n: int, log=None):
    """(name, values) from (name, lo, hi) or "NAME=LO:HI"; log spacing when
    hi/lo >= 10 unless ``log`` says otherwise."""
    if isinstance(spec, str):
        name, sep, rng = spec.partition("=")
        lo, sep2, hi = rng.partition(":")
        try:
            if not (sep and sep2 and name.strip()):
                raise ValueError
            spec = (name.strip(), float(lo), float(hi))
        except ValueError:
            raise ParameterError(f"axis {spec!r}: expected NAME=LO:HI, e.g. hammer.v0=1:6") from None
    if not (isinstance(spec, (list, tuple)) and len(spec) == 3 and isinstance(spec[0], str)):
        raise ParameterError(f"axis {spec!r}: give (name, lo, hi) or 'NAME=LO:HI', "
                             "e.g. 'hammer.v0=1:6'")
    name, lo, hi = spec[0], real(spec[1], f"axis {spec[0]} lo"), real(spec[2], f"axis {spec[0]} hi")
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        raise ParameterError(f"axis {name}: lo = {lo:g} must be below hi = {hi:g}")
    if not (isinstance(n, int) and n >= 2):
        raise ParameterError(f"design map: n = {plain(n)} points per axis; need a whole number >= 2")
    if log is None:
        log = lo > 0 and hi / lo >= 10
    return name, (np.geomspace(lo, hi, n) if log else np.linspace(lo, hi, n))


def design_map(rig: Component | DAE | str, x: tuple[str, float, float] | str,
               y: tuple[str, float, float] | str, *, n: int = 21, params: Mapping[str, float] | None = None, t_end: float = 0.03,
               log: bool | None = None, backend: str = "auto",
               progress: bool | Callable[[int, int], object] | None = None) -> DesignMap:
    """A design map: peak pressure, pulse duration and time of peak over a
    grid of two settings of a rig, computed by one sweep (the chart to see
    which settings give which pulse).

    Parameters
    ----------
    rig : Component, DAE or str
        The rig, its compiled DAE, or a name of ``pdbfs.models.RIGS``.
    x, y : tuple or str
        The axes: ``(name, lo, hi)`` or ``"NAME=LO:HI"``, SI units; a drop
        height ``X.h`` (m) stands for the impact speed ``X.v0``.
    n : int
        Points per axis (>= 2).
    params : mapping of str to float, optional
        Parameter values held fixed, SI units.
    t_end : float
        End time of each run, s.
    log : bool, optional
        Log spacing of both axes (None: an axis whose hi/lo is 10 or more).
    backend : {"auto", "c", "casadi"}
        As in ``simulate``.
    progress : bool or callable, optional
        As in ``sweep``.

    Returns
    -------
    DesignMap
        Each feature as an array over the grid (rows: y, columns: x), NaN
        where a point failed or gave no complete pulse (a warning says how
        many).

    Raises
    ------
    pdbfs.ParameterError
        For a bad axis, the same setting on both axes, or a grid too big for
        the memory: before any run.
    pdbfs.PdbfsError
        When no point of the grid gives a pulse.

    Examples
    --------
    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> m = pdbfs.design_map(paper_rig(), ("hammer.h", 0.1, 1.5), ("oil.k", 1e8, 1e9), n=5)
    >>> m.values["peak_pressure"].shape, m.failed
    ((5, 5), 0)
    >>> f"{m.values['peak_pressure'][-1, -1] / 1e6:.3g} MPa at h = {m.x[-1]} m, k = {m.y[-1]:g} N/m"
    '367 MPa at h = 1.5 m, k = 1e+09 N/m'
    """
    check_t_end(t_end)
    params = mapping(params, "params")
    rig = _rig(rig)
    sim = Simulator.of(rig)
    (xn, xv), (yn, yv) = axis(x, n, log), axis(y, n, log)
    if xn == yn:
        raise ParameterError(f"design map: x and y are both {xn}")
    units = {p.name: p.unit for p in sim.dae.params}
    cols, axis_units = {}, []
    for name, vals in ((xn, xv), (yn, yv)):
        if height_stands_for(sim.dae, name):
            cols[height_stands_for(sim.dae, name)] = [impact_velocity(h) for h in vals]
            axis_units.append("m")
        else:
            cols[name] = list(vals)
            axis_units.append(units.get(name, ""))
    if len(cols) < 2:       # X.h and X.v0: the drop height is the impact speed seen again
        raise ParameterError(f"design map: {xn} and {yn} are the same setting seen twice (a drop "
                             "height stands for the impact speed v0 = sqrt(2 g h)); choose two "
                             "different settings")
    (cx, vx), (cy, vy) = cols.items()
    require(table_bytes(len(vx) * len(vy), 12), f"design map: {len(vx)} x {len(vy)} points",
            "ask for fewer (n, --n)")
    grid = [(a, b) for b in vy for a in vx]          # y rows, x columns
    res = sweep(rig, {cx: [g[0] for g in grid], cy: [g[1] for g in grid]}, grid=False,
                t_end=t_end, n_out=max(2, int(round(t_end / 1e-5)) + 1), params=params, backend=backend,
                progress=progress)
    values = {k: res.values(k).reshape(len(yv), len(xv)) for k in MAPPED}
    failed, no_pulse = _blanks(res, sim.dae.name, len(xv), len(yv), t_end)
    return DesignMap(sim.dae.name, xn, yn, xv, yv, values, failed, *axis_units,
                     no_pulse=no_pulse)


def _blanks(res, rig, nx, ny, t_end):
    """(failed, no_pulse): the points left blank on the map. A map blank
    everywhere is refused (it maps nothing); some blank points are warned of."""
    blank = np.zeros(len(res), bool)
    for k in MAPPED:
        blank |= ~np.isfinite(res.values(k))
    errors = res.frame["error"].to_numpy() if len(res) else np.array([])
    failed = errors != ""
    quiet = blank & ~failed                   # ran, but no pulse (or none that ended)
    where = lambda i: plain({n: float(res.values(n)[i]) for n in res.names})  # noqa: E731
    why = []
    if failed.any():
        i = int(np.flatnonzero(failed)[0])
        why.append(f"{int(failed.sum())} of {len(res)} points failed, first at {where(i)}: "
                   f"{errors[i]}")
    if quiet.any():
        i = int(np.flatnonzero(quiet)[0])
        why.append(f"{int(quiet.sum())} of {len(res)} points gave no complete pulse in "
                   f"[0, {t_end:g}] s, first at {where(i)}")
    if blank.all():
        raise PdbfsError(f"design map of rig {rig}: no point of the {nx} x {ny} grid gives a "
                         f"pulse to map ({'; '.join(why)}); choose settings that strike, or a "
                         "longer t_end")
    if quiet.any():
        warnings.warn(f"design map of rig {rig}: {why[-1]}; left blank on the map",
                      PdbfsWarning, stacklevel=3)
    return int(failed.sum()), int(quiet.sum())
