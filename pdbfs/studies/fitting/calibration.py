"""Calibration: the rig's unknown parameters fitted to a measured trace.

    cal = pdbfs.calibrate(paper_rig(), "kistler.csv", free=["oil.k", "seal.c", "hammer.v0"],
                          fit_offset=True)
    cal.params, cal.std, cal.rms_residual, cal.undetermined

Least squares on the trace's own samples with exact gradients (CVODES
sensitivities, studies/signal_model.py), bounded and scaled unknowns
(studies/unknowns.py), several starts (studies/fitting.py). Parameters the
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
    """What a calibration found. ``params`` maps each free name to its fitted
    value, or None where the trace does not determine it (``undetermined``
    says why; ``held`` gives the value it was held at)."""

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
        """Trace minus fit at the trace's times, in the signal's unit."""
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
        """Trace, fit and residuals against time; saved to ``path`` if given. Returns the Figure."""
        from .reports import plot_fit
        return plot_fit(self, path)

    def to_csv(self, path: str | os.PathLike) -> str | os.PathLike:
        """Write time, trace, fit and residual as CSV (units in the header); returns ``path``."""
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
    """Fit the parameters ``free`` of ``rig`` so that its ``signal`` (default:
    the rig's pressure) matches ``trace`` (a CSV path, a Trace or (t, y)).

    fit_offset  also fit a trigger time shift ``trace.shift`` (s; the model
                runs at t - shift) and a sensor offset ``trace.offset``
    bounds      {name: (lo, hi)} (or "NAME=LO:HI" strings); default: a
                factor 100 either side of the start for positive parameters
    start       {name: value}: where the first start begins (default: the
                rig's value); ``starts`` - 1 more begin on a Latin hypercube
    params      {name: value} held fixed (not free)
    t_end       simulated horizon (default: the trace's last time, plus the
                shift's range); one that ends before the trace is refused
    progress    a function called with the number of simulations run so far
    inputs      the rig's inputs, as simulate takes them (a measured command:
                {"command": (t, u)}), on the trace's clock: they must cover the
                simulated horizon; not with fit_offset (the command and the
                trace share their clock)
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
