"""Design: the settings of a rig that give a wanted pressure pulse.

    pdbfs.design(rig, target="gun.csv", free=["hammer.v0", "oil.k", "seal.c"])
    pdbfs.design(rig, target={"peak_pressure": 150e6, "pulse_duration": 0.009},
                 free=["hammer.h", "oil.k"], bounds={"hammer.h": (0.1, 2.0)})

To a target curve: least squares on the curve's own samples (the same
engine as calibration). To target features (peak pressure, pulse duration
as the summary defines it, time of peak): their exact gradients
(features) drive a bounded least-squares solve; where no setting
within the bounds reaches the targets, the nearest reachable point is
returned with what stops it (a bound, or the features moving together).
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import ParameterError
from pdbfs.simulation import Simulator
from pdbfs.simulation.results.reprs import number, table, values
from pdbfs.simulation.setup.settings import real

from .calibration import _rig
from .features import FEATURES, UNITS
from .least_squares import solve
from .objectives import CurveProblem, FeatureProblem
from .signal_model import DT, SignalModel, signal_of
from .arguments import check_fit_arguments
from .traces import as_trace, check_horizon, check_time_origin
from .free_parameters import DESIGN_RANGE, parse_bounds, rig_unknowns

if TYPE_CHECKING:
    import os

    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from pdbfs.modelling import DAE, Component

    from .traces import Trace

#: relative miss of a feature target below which it counts as reached
REACHED = 1e-4
ALIASES = {"peak": "peak_pressure", "duration": "pulse_duration", "peak_time": "time_of_peak"}


@dataclass
class Design:
    """What a design found: the free parameters' values that give the target
    pulse. Made by ``design``.

    Attributes
    ----------
    rig, signal, unit : str
        The rig's name, the variable designed for and its unit.
    params : dict
        Free name -> designed value (SI units; a drop height in m).
    implied : dict
        Rig parameters set through another (``hammer.v0`` from a drop height).
    reachable : bool
        Whether the target is met.
    limit : str
        Why not, when it is not: which bound or which feature stands in the way.
    targets, features : dict
        Feature targets asked for and the designed pulse's features.
    rms_error, worst_deviation, worst_time : float or None
        For a target curve: its RMS and largest miss (signal's unit) and
        where the largest is (s).
    at_bounds : dict
        Free name -> the bound it ended at.
    units : dict
        Free name -> unit.
    t, y, fit : numpy.ndarray
        Times (s), the target curve (None for feature targets) and the
        designed pulse there.
    evaluations : int
        Simulations run.
    """

    rig: str
    signal: str
    unit: str
    params: dict                       # free name -> designed value
    implied: dict                      # rig parameters set through a transform (v0 from h)
    reachable: bool
    limit: str = ""                    # why not, when not reachable
    targets: dict = field(default_factory=dict)
    features: dict = field(default_factory=dict)   # the designed pulse's features
    rms_error: float | None = None     # target-curve mode
    worst_deviation: float | None = None
    worst_time: float | None = None
    at_bounds: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)
    t: np.ndarray = None               # target curve times, or the designed pulse's grid
    y: np.ndarray = None               # target curve (None in feature mode)
    fit: np.ndarray = None             # the designed pulse at t
    evaluations: int = 0

    def _shown(self) -> tuple[str, list[tuple[str, str]]]:
        rows = [("settings", values(self.params, self.units) or "none"),
                ("targets", "reached" if self.reachable else f"not reached: {self.limit}")]
        if self.targets:
            rows.append(("features", values({k: self.features.get(k) for k in self.targets},
                                            UNITS)))
        elif self.rms_error is not None:
            rows.append(("curve", f"rms error {number(self.rms_error, self.unit)}"))
        if self.at_bounds:
            rows.append(("at a bound", ", ".join(self.at_bounds)))
        return f"Design of rig {self.rig}", rows

    def __repr__(self) -> str:
        title, rows = self._shown()
        return f"<{title}: " + "; ".join(f"{k} {v}" for k, v in rows) + ">"

    def _repr_html_(self) -> str:
        return table(*self._shown())

    def to_dict(self) -> dict:
        """JSON-ready: params, implied, reachable, targets and features or the curve's errors."""
        d = {"rig": self.rig, "signal": self.signal, "params": self.params, "implied": self.implied,
             "units": self.units, "reachable": self.reachable, "at_bounds": self.at_bounds,
             "evaluations": self.evaluations}
        if self.targets:
            d.update(targets=self.targets, features=self.features)
        else:
            d.update(rms_error=self.rms_error, worst_deviation=self.worst_deviation,
                     worst_time=self.worst_time, features=self.features)
        if not self.reachable:
            d["limit"] = self.limit
        return d

    def report(self) -> str:
        """The design as text: the values, the features reached, the bounds hit."""
        from .reports import design_text
        return design_text(self)

    def plot(self, path: str | os.PathLike | None = None) -> Figure:
        """The designed pulse, and the target curve if there is one.

        Parameters
        ----------
        path : str or os.PathLike, optional
            An image file to save the figure to (its format by its suffix).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from .reports import plot_design
        return plot_design(self, path)

    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """Write time, target (if a curve) and designed pulse as CSV (units
        in the header), written whole or not at all.

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.

        Returns
        -------
        str or os.PathLike
            ``path``.
        """
        from .reports import write_columns
        cols = {"time [s]": self.t}
        if self.y is not None:
            cols[f"target [{self.unit}]"] = self.y
        cols[f"designed [{self.unit}]"] = self.fit
        return write_columns(path, cols)


def design(rig: Component | DAE | str,
           target: str | os.PathLike | Trace | tuple[ArrayLike, ArrayLike] | Mapping[str, float], *,
           free: str | Sequence[str],
           bounds: Mapping[str, tuple[float, float]] | Sequence[str] | None = None,
           start: Mapping[str, float] | None = None, params: Mapping[str, float] | None = None,
           signal: str | None = None, t_end: float | None = None, starts: int = 1, seed: int = 0,
           rtol: float = 1e-8,
           atol: float | None = None, dt: float = DT,
           progress: Callable[[int], object] | None = None) -> Design:
    """Inverse design: the settings of a rig that give a target pulse, a
    curve to follow or pulse features to reach (least squares with exact
    gradients, as ``calibrate``).

    Parameters
    ----------
    rig : Component, DAE or str
        The rig, its compiled DAE, or a name of ``pdbfs.models.RIGS``.
    target : str, os.PathLike, Trace, tuple of array_like, or mapping of str to float
        A target curve (a CSV file, a Trace, or ``(t, y)`` in s and the
        signal's unit), or features: ``{"peak_pressure": Pa,
        "pulse_duration": s, "time_of_peak": s}`` (any of them; ``peak``,
        ``duration`` and ``peak_time`` also name them).
    free : str or sequence of str
        The settings to design, each once; a drop height ``X.h`` (m) stands
        for the impact speed ``X.v0`` of a rig whose hammer has one.
    bounds : mapping of str to tuple, or sequence of str, optional
        ``{name: (lo, hi)}`` (or ``"NAME=LO:HI"`` strings), SI units;
        default: a factor 10 either side of the rig's values.
    start : mapping of str to float, optional
        Where the first start begins (default: the rig's values).
    params : mapping of str to float, optional
        Parameter values held fixed, SI units.
    signal : str, optional
        The variable designed for (default: the rig's pressure).
    t_end : float, optional
        The simulated horizon, s (for a curve at least its last time).
    starts : int
        For features, more starts (a Latin hypercube) tried when the first
        does not reach them; for a curve, the starts of the fit.
    seed : int
        The seed of that hypercube.
    rtol, atol : float
        Tolerances of the simulations (``atol`` None: as in ``simulate``).
    dt : float
        The model's sampling step, s, during the pulse.
    progress : callable, optional
        Called with the number of simulations run so far.

    Returns
    -------
    Design
        The designed values, the values they imply (an impact speed), the
        features reached, and whether the target was reached (if not, why).

    Raises
    ------
    pdbfs.ParameterError
        For an unknown target or name, a target that is not a positive
        number, bad bounds, or features no pulse can have together (a peak
        after the pulse's end): before any design run.
    pdbfs.DataError
        For a target curve that cannot be read.

    Examples
    --------
    The drop height and seal friction of the paper's rig for a 120 MPa pulse
    of 12 ms:

    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> d = pdbfs.design(paper_rig(), {"peak_pressure": 120e6, "pulse_duration": 0.012},
    ...                  free=["hammer.h", "seal.c"])
    >>> d.reachable, f"{d.params['hammer.h']:.3g} m", f"{d.implied['hammer.v0']:.3g} m/s"
    (True, '0.637 m', '3.53 m/s')
    >>> f"{d.features['peak_pressure'] / 1e6:.4g} MPa"
    '120 MPa'
    """
    start, params = check_fit_arguments(free=free, bounds=bounds, start=start, params=params,
                                        starts=starts, t_end=t_end, seed=seed, signal=signal)
    if isinstance(target, dict):     # features; a curve: as_trace says what is wrong with it
        target = {k: real(v, f"target {k}") for k, v in target.items()}
    rig = _rig(rig)
    sim = Simulator.of(rig)
    dae = sim.dae
    signal = signal_of(dae, signal)
    unit = next(v.unit for v in dae.y_info if v.name == signal)
    unknowns, p0 = rig_unknowns(sim, free, bounds=parse_bounds(bounds), start=start,
                                fixed=params, factor=DESIGN_RANGE)
    targets = [u.target for u in unknowns]
    z0 = np.array([u.z(u.ref) for u in unknowns])
    lo, hi = (np.array(b) for b in zip(*(u.z_bounds for u in unknowns)))
    if isinstance(target, dict):
        goals = _feature_targets(target)
        horizon = t_end or _horizon(goals, getattr(rig, "default_t_end", 0.02))
        check_peak_in_pulse(rig, unknowns, params, goals, horizon)
        model = SignalModel(sim, signal, targets, horizon, p0, dt=dt, rtol=rtol, atol=atol,
                            progress=progress)
        prob = FeatureProblem(model, unknowns, goals)
        fit = solve(prob, z0, lo, hi, starts=1)
        if np.max(np.abs(fit.residual)) > REACHED and starts > 1:
            more = solve(prob, fit.z, lo, hi, starts=starts, seed=seed)
            fit = more if more.cost < fit.cost else fit
        feats, _, s = prob.features(fit.z, sens=False)
        miss = {k: (feats[k] - t) / t for k, t in goals.items()}
        reached = max(abs(m) for m in miss.values()) <= REACHED
        out = Design(dae.name, signal, unit, {}, {}, reached, targets=goals,
                     features={k: feats[k] for k in feats}, t=s.t, fit=s.y)
        if not reached:
            out.limit = _limit(unknowns, fit, feats, goals, prob)
    else:
        trace = as_trace(target, "target")
        check_horizon(t_end, trace, "target curve")
        check_time_origin(trace, getattr(rig, "default_t_end", 0.02))
        horizon = max(float(trace.t[-1]), t_end or 0.0)
        model = SignalModel(sim, signal, targets, horizon, p0, dt=dt, rtol=rtol, atol=atol,
                            progress=progress)
        scale = float(np.max(np.abs(trace.y))) or 1.0
        prob = CurveProblem(model, unknowns, trace, scale)
        fit = solve(prob, z0, lo, hi, starts=starts, seed=seed)
        y_fit, _ = prob.curve(fit.z, sens=False)
        dev = y_fit - trace.y
        k = int(np.argmax(np.abs(dev)))
        out = Design(dae.name, signal, unit, {}, {}, True, rms_error=float(np.sqrt(np.mean(dev ** 2))),
                     worst_deviation=float(abs(dev[k])), worst_time=float(trace.t[k]),
                     t=trace.t, y=trace.y, fit=y_fit)
    for u, z, a in zip(unknowns, fit.z, fit.active):
        v = u.value(z)
        out.params[u.name] = v
        out.units[u.name] = u.unit
        if u.height:
            out.implied[u.target] = u.rig_value(v)
        if a:
            out.at_bounds[u.name] = ("lower", u.lo) if a < 0 else ("upper", u.hi)
    out.evaluations = model.evaluations
    return out


def _feature_targets(target: dict) -> dict:
    goals = {}
    for k, v in target.items():
        k = ALIASES.get(k, k)
        if k not in FEATURES:
            raise ParameterError(f"unknown design target {k!r}; choose from {', '.join(FEATURES)}")
        if v is None:
            continue
        v = float(v)
        if not (np.isfinite(v) and v > 0):
            raise ParameterError(f"design target {k} = {v:g} {UNITS[k]}: must be a positive number")
        goals[k] = v
    if not goals:
        raise ParameterError("no design target: give a curve, or at least one of "
                             + ", ".join(FEATURES))
    return goals


def check_peak_in_pulse(rig, unknowns, params, goals, horizon):
    """Refuse a time of peak that comes after a pulse of the duration asked
    has ended, wherever the free parameters are within their bounds: the
    peak lies inside the pulse, which starts by the latest peak the rig
    has at its bounds' corners (or the ends of each bound, past 3 free
    parameters). Nothing is refused where a probe has no peak in the horizon."""
    t_peak, duration = goals.get("time_of_peak"), goals.get("pulse_duration")
    if t_peak is None or duration is None or t_peak <= duration:
        return                           # a pulse from the start of the run can hold it
    from itertools import product

    from pdbfs.errors import PdbfsError

    from ..sweeps import Points, sweep
    mid = [u.ref for u in unknowns]
    if len(unknowns) <= 3:
        rows = [mid] + [list(c) for c in product(*[(u.lo, u.hi) for u in unknowns])]
    else:
        rows = [mid] + [mid[:i] + [b] + mid[i + 1:] for i, u in enumerate(unknowns)
                        for b in (u.lo, u.hi)]
    X = [[u.rig_value(v) for u, v in zip(unknowns, row)] for row in rows]
    try:
        probes = sweep(rig, Points([u.target for u in unknowns], X, {"kind": "design probes"}),
                       t_end=horizon, params=params, progress=False, workers=1)
        peaks = probes.values("time_of_peak")
    except (PdbfsError, KeyError):
        return                           # the design itself says what is wrong
    if not np.all(np.isfinite(peaks)):
        return
    latest = float(np.max(peaks))
    if t_peak > latest + 2.0 * duration:
        free = ", ".join(u.name for u in unknowns)
        raise ParameterError(
            f"design targets: time_of_peak = {t_peak:g} s comes after a pulse of "
            f"pulse_duration = {duration:g} s has ended: with {free} within their bounds "
            f"rig {probes.rig} peaks by {latest:.4g} s (at the bounds' ends), so its pulse "
            f"starts by then; ask for a time of peak inside the pulse, or free a parameter "
            "that delays the blow (a gap, a start position, a drop height)")


def _horizon(goals, default):
    """Long enough for the pulse asked for to rise and fall again."""
    return max(default, 3.0 * goals.get("pulse_duration", 0.0), 4.0 * goals.get("time_of_peak", 0.0))


def _limit(unknowns, fit, feats, goals, prob) -> str:
    """Why the targets were not reached, in words."""
    near = ", ".join(f"{k} = {feats[k]:.4g} {UNITS[k]}" for k in goals)
    bound = [f"{u.name} at its {'lower' if a < 0 else 'upper'} bound "
             f"{u.lo if a < 0 else u.hi:.4g} {u.unit}" for u, a in zip(unknowns, fit.active) if a]
    if bound:
        return f"not reachable within the bounds: nearest reachable {near}; stopped by " \
               + "; ".join(bound)
    rank = np.linalg.matrix_rank(fit.jac, tol=1e-6 * max(np.abs(fit.jac).max(), 1e-300))
    return (f"not reachable: nearest reachable {near}; the free parameters ("
            + ", ".join(u.name for u in unknowns) + f") move the {len(goals)} target(s) together "
            f"(rank {rank} here): free another parameter or relax a target")
