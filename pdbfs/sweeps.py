"""Parameter sweeps: one compiled rig, many parameter points.

    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [1.87, 2.73, 4.23, 5.50]})
    res.to_csv("sweep.csv")
    for pt in res: print(pt.params, pt.summary or pt.error)

The rig is compiled once and every point runs on the same cached SUNDIALS
integrator (``Simulator.of(rig)``); nothing is rebuilt between points.

Parallelism: a point costs about 6 ms of integration and about 11 ms of
summary (peaks and crossings are located by root finding on the solution), so
the work is spread over forked worker processes, each running whole points
(integration and summary). CasADi's ``map(N, 'thread')`` over the integrator
was measured slower than a serial loop on this machine (6.7 vs 5.5 ms per
point, 2 cores) and would leave the summaries serial, so it is not used.
Below ``PARALLEL_MIN_POINTS`` points, or on one core, the sweep runs serially.
"""
from __future__ import annotations

import csv
import itertools
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError, PdbfsError

#: below this many points a sweep runs serially (forking costs ~50-100 ms)
PARALLEL_MIN_POINTS = 8
#: show a progress bar for sweeps expected to take longer than this, s
PROGRESS_AFTER = 2.0


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
        from .summary import UNITS
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
        from .summary import UNITS
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


# ------------------------------------------------------------------ the points
def points_of(values: dict, grid: bool = True) -> list[dict]:
    """The parameter points of a sweep: the Cartesian product of the lists
    (``grid=True``) or the lists read as columns of equal length."""
    if not isinstance(values, dict) or not values:
        raise ParameterError("sweep: give the values as a non-empty dict "
                             "{parameter name: list of values}")
    cols = {}
    for name, vals in values.items():
        if not isinstance(name, str):
            raise ParameterError(f"sweep: parameter name {name!r} is not a string")
        if isinstance(vals, (str, bytes)) or np.isscalar(vals):
            vals = [vals]
        vals = list(np.asarray(vals, dtype=object).ravel()) if isinstance(vals, np.ndarray) \
            else list(vals)
        if not vals:
            raise ParameterError(f"sweep: no values given for {name}")
        cols[name] = vals
    names = list(cols)
    if grid:
        return [dict(zip(names, combo)) for combo in itertools.product(*cols.values())]
    lengths = {n: len(v) for n, v in cols.items()}
    if len(set(lengths.values())) > 1:
        raise ParameterError("sweep(grid=False) needs lists of equal length, got "
                             + ", ".join(f"{n}: {k}" for n, k in lengths.items()))
    n = next(iter(lengths.values()))
    return [{name: cols[name][i] for name in names} for i in range(n)]


# ------------------------------------------------------------------ the sweep
_WORK = None   # (Simulator, run kwargs, trajectories): inherited by forked workers


def sweep(rig, values: dict, *, grid: bool = True, trajectories: bool = False,
          t_end: float = 0.02, n_out: int = 2001, params: dict | None = None,
          start: dict | None = None, rtol: float = 1e-8, atol: float = 1e-10,
          method: str = "adams", max_step: float | None = None, backend: str = "casadi",
          workers: int | None = None, progress: bool | None = None) -> SweepResult:
    """Simulate ``rig`` at every point of ``values`` and summarise each.

    rig           a Component, its compiled DAE, or a name from pdbfs.models.RIGS
    values        {parameter name: list of values}
    grid          True: every combination; False: the lists are columns of
                  equal length (point i takes the i-th value of each)
    trajectories  keep each point's full Result (``point.result``)
    params        parameters fixed for every point
    t_end, n_out, start, rtol, atol, method, max_step, backend: as in pdbfs.simulate
    workers       processes to use (None: automatic; 1: serial)
    progress      show a progress bar on stderr (None: when the sweep is
                  expected to take more than a couple of seconds)

    A point that fails (a bad value, a solver failure: any PdbfsError) is
    returned with its parameters and the reason; the others still run.
    An unknown parameter name fails the whole sweep at once.
    """
    global _WORK
    from .simulation import Simulator
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        rig = RIGS[rig]()
    sim = Simulator.of(rig)
    pts = points_of(values, grid)
    names = list(pts[0])
    fixed = dict(params or {})
    clash = sorted(set(fixed) & set(names))
    if clash:
        raise ParameterError(f"sweep: {', '.join(clash)} is both swept and fixed in params=")
    # names first: an unknown name is an error of the whole sweep, not of a point
    sim.param_vector({n: _probe_value(sim, n) for n in list(names) + list(fixed)})
    sim.param_vector(fixed)
    kwargs = dict(t_end=t_end, n_out=n_out, start=start, rtol=rtol, atol=atol, method=method,
                  max_step=max_step, backend=backend)
    sim.grid(t_end, n_out)   # bad t_end / n_out: one clear error now
    sim.check_settings(rtol, atol, method, max_step, backend=backend)
    if backend == "c":
        sim.compiled()       # built once here, inherited by forked workers
    else:
        sim.integrator(sim.grid(t_end, n_out), rtol, atol, method, max_step)

    n = len(pts)
    if workers is None:
        workers = _auto_workers(n)
    elif not (isinstance(workers, int) and workers >= 1):
        raise ParameterError(f"sweep: workers = {workers!r} must be a whole number >= 1")
    workers = min(workers, n)
    if workers > 1 and not _can_fork():
        workers = 1

    t0 = time.perf_counter()
    bar = _Progress(n, progress, sim.dae.name)
    jobs = [(i, {**fixed, **p}) for i, p in enumerate(pts)]
    raw = {}
    _WORK = (sim, kwargs, trajectories)
    try:
        if workers == 1:
            for job in jobs:
                i, out = _run_point(job)
                raw[i] = out
                bar.update(1)
        else:
            import multiprocessing as mp
            chunk = max(1, min(16, math.ceil(n / (workers * 4))))
            chunks = [jobs[k:k + chunk] for k in range(0, n, chunk)]
            with mp.get_context("fork").Pool(workers) as pool:
                for outs in pool.imap_unordered(_run_chunk, chunks):
                    for i, out in outs:
                        raw[i] = out
                    bar.update(len(outs))
    finally:
        _WORK = None
        bar.close()

    res = SweepResult(rig=sim.dae.name, names=names, elapsed=time.perf_counter() - t0,
                      workers=workers)
    for i, p in enumerate(pts):
        out = raw[i]
        pt = SweepPoint(index=i, params=dict(p))
        if out[0] == "ok":
            pt.summary = out[1]
            if trajectories:
                pt.result = _rebuild(sim, out[2])
        else:
            pt.error_type, pt.error = out[1], out[2]
        res.points.append(pt)
    return res


def _probe_value(sim, name):
    """A valid value of parameter ``name`` (its default), to check names only."""
    for info in sim.dae.params:
        if info.name == name:
            return info.value
    return 0.0   # unknown: param_vector raises with a hint


def _auto_workers(n: int) -> int:
    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    if n < PARALLEL_MIN_POINTS or (cpus or 1) < 2:
        return 1
    return min(cpus, n)


def _can_fork() -> bool:
    import multiprocessing as mp
    return "fork" in mp.get_all_start_methods()


def _run_chunk(jobs):
    return [_run_point(j) for j in jobs]


def _run_point(job):
    i, params = job
    sim, kwargs, keep = _WORK
    try:
        res = sim.run(params=params, **kwargs)
        summary = res.summary()
        if keep:   # the Result without its Simulator (rebuilt in the parent's)
            state = {k: v for k, v in vars(res).items() if k != "_sim"}
            return i, ("ok", summary, state)
        return i, ("ok", summary)
    except PdbfsError as err:
        return i, ("error", type(err).__name__, str(err))
    except (ArithmeticError, ValueError, RuntimeError) as err:   # anything the summary hits
        return i, ("error", type(err).__name__, f"{err}")


def _rebuild(sim, state):
    from .result import Result
    res = Result.__new__(Result)
    res.__dict__.update(state)
    res._sim = sim
    return res


class _Progress:
    """tqdm if installed, else a one-line bar on stderr; shown only when
    asked, or (progress=None) once the sweep looks like lasting a while."""

    def __init__(self, total, progress, label):
        self.total, self.done, self.progress = total, 0, progress
        self.label = label
        self.t0 = time.perf_counter()
        self.bar = None
        self.shown = False
        if progress:
            self._open()

    def _open(self):
        self.shown = True
        try:
            from tqdm import tqdm
            self.bar = tqdm(total=self.total, initial=self.done, desc=f"sweep {self.label}",
                            unit="pt", file=sys.stderr, leave=False)
        except ImportError:
            self.bar = None

    def update(self, k):
        self.done += k
        if self.progress is None and not self.shown and self.done < self.total:
            elapsed = time.perf_counter() - self.t0
            if elapsed / self.done * self.total > PROGRESS_AFTER and sys.stderr.isatty():
                self._open()
                return
        if not self.shown:
            return
        if self.bar is not None:
            self.bar.update(k)
        else:
            w = 30
            f = int(w * self.done / self.total)
            sys.stderr.write(f"\rsweep {self.label} [{'#' * f}{'.' * (w - f)}] "
                             f"{self.done}/{self.total}")
            sys.stderr.flush()

    def close(self):
        if not self.shown:
            return
        if self.bar is not None:
            self.bar.close()
        else:
            sys.stderr.write("\n")
