"""Calibration: the rig's unknown parameters fitted to a measured trace.

    cal = pdbfs.calibrate(paper_rig(), "kistler.csv", free=["oil.k", "seal.c", "hammer.v0"],
                          fit_offset=True)
    cal.params, cal.std, cal.rms_residual, cal.undetermined

Least squares on the trace's own samples with exact gradients (CVODES
sensitivities: signal_model), bounded and scaled unknowns (free_parameters),
several starts (least_squares). Parameters the
trace does not determine are named, held at their start values and left
out of the fit: no made-up value is reported for them.
"""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import DataError, ParameterError, PdbfsError
from pdbfs.simulation import Simulator
from pdbfs.simulation.results.reprs import number, table
from pdbfs.simulation.setup.input_traces import drive_of

from .least_squares import distinct_optima, optimum_of_each_start, solve, statistics
from .objectives import OFFSET, SHIFT, CurveProblem, offset_unknowns
from .signal_model import DT, SignalModel, pulse_end, signal_of
from .arguments import check_fit_arguments
from .traces import as_trace, check_horizon, check_time_origin
from .free_parameters import CALIBRATION_RANGE, parse_bounds, rig_unknowns

if TYPE_CHECKING:
    import os

    from matplotlib.figure import Figure
    from numpy.typing import ArrayLike

    from pdbfs.modelling import DAE, Component

    from .traces import Trace


@dataclass
class Calibration:
    """What a calibration found. Made by ``calibrate``.

    Attributes
    ----------
    rig, signal, unit : str
        The rig's name, the variable fitted and its unit.
    params : dict
        Each free name -> its fitted value, SI units, or None where the
        trace does not determine it (``undetermined`` says why; ``held``
        gives the value it was held at). With ``fit_offset``, also
        ``trace.shift`` (s) and ``trace.offset`` (the signal's unit).
    std : dict
        Free name -> the standard error of its value (None where undetermined).
    corr : dict
        ``{name: {name: correlation}}`` over the determined unknowns.
    rms_residual, sigma : float
        The RMS of trace minus fit, and the residuals' standard deviation
        (degrees of freedom counted), in the signal's unit.
    undetermined, held : dict
        Name -> why the trace does not determine it, and the value it was
        held at.
    at_bounds : dict
        Name -> the bound ("lower" / "upper") its value reached.
    starts : list of dict
        Each start's end: its cost, evaluations, status, and which optimum
        it reached (0: the best; None: the start failed).
    optima : int
        How many distinct optima the starts reached.
    t, y, fit : numpy.ndarray
        The trace's times (s) and values, and the fitted model there.
    evaluations : int
        Simulations run.
    units : dict
        Name -> unit of each fitted value.
    """

    rig: str
    signal: str
    unit: str
    params: dict
    std: dict
    corr: dict                # {name: {name: correlation}} over the determined unknowns
    rms_residual: float
    sigma: float              # residual standard deviation (degrees of freedom counted)
    undetermined: dict        # name -> reason
    held: dict                # name -> value it was held at
    at_bounds: dict           # name -> "lower" / "upper" bound value reached
    starts: list = field(default_factory=list)
    optima: int = 1
    t: np.ndarray = None      # the trace
    y: np.ndarray = None
    fit: np.ndarray = None    # the model at the trace's times
    evaluations: int = 0
    units: dict = field(default_factory=dict)

    @property
    def residuals(self) -> np.ndarray:
        """Trace minus fit at the trace's times, in the signal's unit (a numpy array)."""
        return self.y - self.fit

    def _shown(self) -> tuple[str, list[tuple[str, str]]]:
        fitted = {k: v for k, v in self.params.items() if v is not None}
        rows = [("fitted", ", ".join(f"{k} {number(v, self.units.get(k, ''))} +- "
                                     f"{number(self.std.get(k), self.units.get(k, ''))}"
                                     for k, v in fitted.items())
                 or "nothing")]
        if self.undetermined:
            rows.append(("undetermined", ", ".join(self.undetermined)))
        if self.at_bounds:
            rows.append(("at a bound", ", ".join(self.at_bounds)))
        rows.append(("residual", f"rms {number(self.rms_residual, self.unit)} of {self.signal}"))
        return f"Calibration of rig {self.rig}", rows

    def __repr__(self) -> str:
        title, rows = self._shown()
        return f"<{title}: " + "; ".join(f"{k} {v}" for k, v in rows) + ">"

    def _repr_html_(self) -> str:
        return table(*self._shown())

    def to_dict(self) -> dict:
        """JSON-ready: params, std, rms_residual, correlation, undetermined, ..."""
        return {"rig": self.rig, "signal": self.signal, "params": self.params, "std": self.std,
                "units": self.units, "rms_residual": self.rms_residual, "sigma": self.sigma,
                "correlation": self.corr, "undetermined": self.undetermined, "held": self.held,
                "at_bounds": self.at_bounds, "starts": self.starts, "distinct_optima": self.optima,
                "evaluations": self.evaluations}

    def report(self) -> str:
        """The fit as text: each value with its standard deviation, correlations, warnings."""
        from .reports import calibration_text
        return calibration_text(self)

    def plot(self, path: str | os.PathLike | None = None) -> Figure:
        """Trace, fit and residuals against time.

        Parameters
        ----------
        path : str or os.PathLike, optional
            An image file to save the figure to (its format by its suffix).

        Returns
        -------
        matplotlib.figure.Figure
            The figure.
        """
        from .reports import plot_fit
        return plot_fit(self, path)

    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """Write time, trace, fit and residual as CSV (units in the header),
        written whole or not at all.

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
        return write_columns(path, {"time [s]": self.t, f"trace [{self.unit}]": self.y,
                                    f"fit [{self.unit}]": self.fit,
                                    f"residual [{self.unit}]": self.residuals})


def calibrate(rig: Component | DAE | str, trace: str | os.PathLike | Trace | tuple[ArrayLike, ArrayLike],
              free: str | Sequence[str], *, signal: str | None = None, fit_offset: bool = False,
              t_end: float | None = None,
              bounds: Mapping[str, tuple[float, float]] | Sequence[str] | None = None,
              start: Mapping[str, float] | None = None, params: Mapping[str, float] | None = None,
              starts: int = 3, seed: int = 0, rtol: float = 1e-8, atol: float | None = None,
              dt: float = DT, progress: Callable[[int], object] | None = None,
              inputs: Mapping[str, object] | None = None) -> Calibration:
    """Fit a rig's unknown parameters to a measured trace: least squares on
    the trace's own samples, with exact gradients (CVODES sensitivities),
    bounded and scaled unknowns, and several starts.

    Parameters the trace does not determine are named, held at their start
    values and left out of the fit: no made-up value is reported for them.

    Parameters
    ----------
    rig : Component, DAE or str
        The rig, its compiled DAE, or a name of ``pdbfs.models.RIGS``.
    trace : str, os.PathLike, Trace or tuple of array_like
        The measurement: a CSV file (time first; units in the header are
        converted to SI), an NI TDMS or ASAM MDF file (the extra ``[lab]``),
        a Trace, or ``(t, y)`` arrays in s and the signal's SI unit.
    free : str or sequence of str
        The parameters to fit, each once.
    signal : str, optional
        The rig variable the trace measures (default: the rig's pressure).
    fit_offset : bool
        Also fit a trigger time shift ``trace.shift`` (s; the model runs at
        t - shift) and a sensor offset ``trace.offset``.
    t_end : float, optional
        The simulated horizon, s (default: the trace's last time, plus the
        shift's range); one that ends before the trace is refused.
    bounds : mapping of str to tuple, or sequence of str, optional
        ``{name: (lo, hi)}`` (or ``"NAME=LO:HI"`` strings), SI units;
        default: a factor 100 either side of the start for positive
        parameters.
    start : mapping of str to float, optional
        Where the first start begins (default: the rig's values).
    params : mapping of str to float, optional
        Parameter values held fixed (not free), SI units.
    starts : int
        Starts of the fit: the first at ``start``, the others on a Latin
        hypercube within the bounds.
    seed : int
        The seed of that hypercube.
    rtol, atol : float
        Tolerances of the simulations (``atol`` None: as in ``simulate``).
    dt : float
        The model's sampling step, s, during the pulse.
    progress : callable, optional
        Called with the number of simulations run so far.
    inputs : mapping of str to trace, number or callable, optional
        The rig's inputs, as ``simulate`` takes them (a measured command:
        ``{"command": (t, u)}``), on the trace's clock: they must cover the
        simulated horizon. Not with ``fit_offset`` (the command and the
        trace share their clock).

    Returns
    -------
    Calibration
        The fitted values, their standard errors and correlations, the
        residual, and what the trace does not determine.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown or repeated name, bad bounds or settings: before any
        simulation.
    pdbfs.DataError
        For a trace that cannot be read, or whose units or times cannot be
        the signal's.

    Examples
    --------
    The example trace shipped with pdbfs (a measured-like pulse of the paper
    rig), three rig parameters and the recorder's trigger delay and offset
    fitted from one start (the default, three, guards against a start that
    stalls):

    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> trace = pdbfs.example_data("kistler_synthetic.csv")
    >>> cal = pdbfs.calibrate(paper_rig(), trace, free=["oil.k", "seal.c", "hammer.v0"],
    ...                       fit_offset=True, starts=1)
    >>> {k: f"{cal.params[k]:.3g}" for k in ("oil.k", "seal.c", "hammer.v0", "trace.shift")}
    {'oil.k': '3.1e+08', 'seal.c': '6.01e+04', 'hammer.v0': '3.2', 'trace.shift': '0.0012'}
    >>> f"{cal.rms_residual / 1e6:.2f} MPa", cal.undetermined
    ('0.49 MPa', {})
    """
    start, params = check_fit_arguments(free=free, bounds=bounds, start=start, params=params,
                                        starts=starts, t_end=t_end, seed=seed, signal=signal)
    sim = Simulator.of(_rig(rig))
    dae = sim.dae
    signal = signal_of(dae, signal)
    trace = as_trace(trace, signal=signal)
    check_horizon(t_end, trace)
    bounds = parse_bounds(bounds)
    own = {k: bounds.pop(k) for k in (SHIFT, OFFSET) if k in bounds}
    unknowns, p0 = rig_unknowns(sim, free, bounds=bounds, start=start, fixed=params,
                                factor=CALIBRATION_RANGE)
    targets = [u.target for u in unknowns]
    unit = next(v.unit for v in dae.y_info if v.name == signal)
    check_trace_fits(trace, unit, signal, getattr(_rig(rig), "default_t_end", 0.02))
    if inputs and fit_offset:
        raise ParameterError("calibrate: inputs and fit_offset together: the inputs share the "
                             "trace's clock, so a trigger shift between them is not fitted")
    if inputs:                 # checked now, over the horizon simulated
        drive_of(dae, inputs, np.array([0.0, max(float(trace.t[-1]), t_end or 0.0)]))
    done = pulse_end(sim, p0, float(trace.t[-1]), inputs)
    fine = None if done is None else max(5.0 * done, 0.02)
    # after the pulse, twice the trace's own samples there (a quiet record needs no more)
    coarse = 2 * int(np.sum(trace.t > (fine or 0.0))) + 100
    horizon = float(trace.t[-1])
    if fit_offset:
        probe = SignalModel(sim, signal, targets, horizon, p0, dt=dt, rtol=rtol, atol=atol,
                            fine_until=fine, coarse=coarse)
        s0 = probe(np.array([u.rig_value(u.ref) for u in unknowns]), sens=False)
        extra = offset_unknowns(trace, (s0.t, s0.y), unit)
        for u in extra:
            if u.name in own:
                u.lo, u.hi = own[u.name]
                u.ref = min(max(u.ref, u.lo), u.hi)
        unknowns += extra
        horizon = float(trace.t[-1] - extra[0].lo)
    elif own:
        raise ParameterError("bounds of trace.shift / trace.offset need fit_offset (--fit-offset)")
    if horizon <= 0:
        raise DataError(f"{trace.source}: every sample lies before the impact (t <= 0)")
    model = SignalModel(sim, signal, targets, max(horizon, t_end or 0.0), p0, dt=dt, rtol=rtol,
                        atol=atol, fine_until=fine, coarse=coarse, progress=progress,
                        inputs=inputs)
    scale = float(np.max(np.abs(trace.y))) or 1.0
    return _fit(dae.name, signal, unit, model, unknowns, trace, scale, starts, seed)


def check_trace_fits(trace, unit, signal, pulse_horizon):
    """Refuse a trace whose units cannot be the signal's, or whose times,
    given without a unit, are implausible for the rig (ms read as s)."""
    if trace.unit and unit and trace.unit != unit:
        raise DataError(f"{trace.source}: the signal is in {trace.unit}, but {signal} is in "
                        f"{unit}; choose the matching column (--signal) or rig variable")
    check_time_origin(trace, pulse_horizon)
    if not trace.time_unit and trace.span > 100 * pulse_horizon:
        raise DataError(f"{trace.source}: its times span {trace.span:.6g} s without a unit, "
                        f"for a pulse of about {pulse_horizon * 1e3:.0f} ms; if they are ms, "
                        "say so in the header (time [ms])")


def _rig(rig):
    """A rig, or the rig of that name in pdbfs.models.RIGS."""
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        return RIGS[rig]()
    return rig


def _fit(rig_name, signal, unit, model, unknowns, trace, scale, starts, seed) -> Calibration:
    """Fit, then hold what the trace does not determine and fit the rest again."""
    held, undetermined = {}, {}
    z_start = {u.name: u.z(u.ref) for u in unknowns}
    first = None
    while True:
        prob = CurveProblem(model, unknowns, trace, scale, held)
        active = prob.unknowns
        z0 = np.array([z_start[u.name] for u in active])
        lo, hi = (np.array(b) for b in zip(*(u.z_bounds for u in active)))
        fit = solve(prob, z0, lo, hi, starts=starts if first is None else 1, seed=seed)
        first = first or fit
        st = statistics(fit.residual * scale, fit.jac * scale)
        if not st.undetermined:
            break
        names = [u.name for u in active]
        for group in st.entangled:
            rest = [names[j] for j in group[1:]]
            undetermined[names[group[0]]] = (
                f"the trace does not separate it from {', '.join(rest)} (fitted with it held)"
                if rest else "the trace does not depend on it")
        for i in st.loose:
            undetermined[names[i]] = "its standard error exceeds the value itself (a factor e)"
        for i in st.undetermined:
            held[names[i]] = active[i].ref
        if len(held) == len(unknowns):
            raise PdbfsError("the trace determines none of the free parameters: "
                             + "; ".join(f"{k}: {v}" for k, v in undetermined.items()))
        z_start.update({n: z for n, z in zip(names, fit.z)})   # go on from the optimum
    values = {u.name: u.value(z) for u, z in zip(active, fit.z)}
    std = {u.name: float(u.dvalue(z) * s) for u, z, s in zip(active, fit.z, st.std_z)}
    corr = {a.name: {b.name: float(st.corr[i, j]) for j, b in enumerate(active)}
            for i, a in enumerate(active)}
    at_bounds = {u.name: ("lower", u.lo) if a < 0 else ("upper", u.hi)
                 for u, a in zip(active, fit.active) if a}
    y_fit, _ = prob.curve(fit.z, sens=False)
    order = [u.name for u in unknowns]
    return Calibration(
        rig=rig_name, signal=signal, unit=unit, params={n: values.get(n) for n in order},
        std={n: std.get(n) for n in order}, corr=corr,
        rms_residual=float(np.sqrt(np.mean((trace.y - y_fit) ** 2))), sigma=st.sigma,
        undetermined=undetermined, held=held, at_bounds=at_bounds,
        starts=[{"cost": s.cost, "evaluations": s.iterations, "status": s.status,
                 "optimum": w}   # 0: the best one; None: the start failed
                for s, w in zip(first.starts, optimum_of_each_start(first))],
        optima=distinct_optima(first), t=trace.t, y=trace.y, fit=y_fit,
        evaluations=model.evaluations, units={u.name: u.unit for u in unknowns})
