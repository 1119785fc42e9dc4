"""Global sensitivity: which settings matter for the pulse. Sobol' first-order
and total indices (SALib, Saltelli's sampling scheme) of pulse features with
respect to parameters varied over ranges, computed by one sweep.

    s = pdbfs.sensitivity(paper_rig(), {"hammer.v0": (1.5, 5.5), "oil.k": (1e8, 1e9),
                                        "seal.c": (2.5e3, 2.5e6, "log")}, n=1024)
    print(s.table()); s.plot("sobol.png")

A range given as (lo, hi, "log") is sampled uniformly in its logarithm (a
seal friction spanning three decades); the indices then refer to the
logarithm of that parameter.
"""
from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import ParameterError, PdbfsError, PdbfsWarning, SampleTooSmallWarning, plain, require_extra
from pdbfs.simulation.setup.memory import require, table_bytes
from pdbfs.simulation.setup.settings import mapping, name_list, real

from .sweeps.sampling import Points, _check_range
from .sweeps import sweep

if TYPE_CHECKING:
    import os

    from distributed import Client
    from matplotlib.figure import Figure

    from pdbfs.modelling import DAE, Component

OUTPUTS = ("peak_pressure", "time_of_peak", "pulse_duration")
#: below this base sample the bootstrap intervals mean nothing (N = 1 gives
#: S1 = 1.333 +- 0): the indices are always flagged
MIN_N = 64
#: a point whose pulse outlasts the horizon is run again over this many
#: horizons (the summary is the same whatever the horizon, once the pulse is in it)
FOLLOW = 20


@dataclass
class Sensitivity:
    """Sobol' indices of summary outputs with respect to rig parameters.

    Attributes
    ----------
    names : list of str
        The parameters, sampled over ``ranges`` (name -> (low, high[, log])).
    outputs : list of str
        The summary keys analysed.
    S1, ST : dict
        Output -> first-order and total indices, one per parameter.
    S1_conf, ST_conf : dict
        Output -> half-widths of their 95 % confidence intervals.
    n, points : int
        The base sample size N and the simulations run, N (D + 2).
    ranges : dict
        Parameter -> (low, high, log), SI units.
    undefined : dict
        Output -> why it has no indices.
    """

    names: list                # parameters
    outputs: list              # summary keys
    S1: dict                   # output -> array over names
    S1_conf: dict              # half-width of the 95 % confidence interval
    ST: dict
    ST_conf: dict
    n: int                     # base sample size N
    points: int                # simulations: N (D + 2)
    ranges: dict
    undefined: dict = None     # output -> why it has no indices (undefined at some points)

    #: a confidence half-width above this leaves an index meaningless
    MAX_CONF = 0.1
    #: an index outside [0, 1] by more than this is impossible, whatever the interval
    SLACK = 0.01

    def problems(self) -> list[str]:
        """Why the sample is too small for the indices to mean anything: N
        below 64, an index outside [0, 1], a first-order index below 0
        beyond its 95 % interval or above the total one, or a 95 % interval
        wider than +-0.1 (``MAX_CONF``).

        Returns
        -------
        list of str
            One line per problem (empty: the indices can be read).
        """
        out = [f"N = {self.n} is below {MIN_N}: too few points for Sobol' indices"] \
            if self.n < MIN_N else []
        for o in self.outputs:
            for i, p in enumerate(self.names):
                s1, st = float(self.S1[o][i]), float(self.ST[o][i])
                c1, ct = float(self.S1_conf[o][i]), float(self.ST_conf[o][i])
                outside = [f"{k} = {v:.3g}" for k, v in (("S1", s1), ("ST", st))
                           if not -self.SLACK <= v <= 1 + self.SLACK]
                if outside:
                    out.append(f"{o}/{p}: {' and '.join(outside)} outside [0, 1]")
                elif not (np.isfinite(c1) and np.isfinite(ct)):
                    out.append(f"{o}/{p}: no confidence interval")
                elif s1 < -max(c1, 1e-3):
                    out.append(f"{o}/{p}: first-order index {s1:.2g} < 0")
                elif s1 > st:
                    out.append(f"{o}/{p}: first-order index {s1:.3f} > total {st:.3f}")
                elif max(c1, ct) > self.MAX_CONF:
                    out.append(f"{o}/{p}: 95 % interval +-{max(c1, ct):.3f}")
        return out

    def to_dict(self) -> dict:
        """JSON-ready: the indices by output and parameter, with reliability and problems."""
        return {"parameters": self.names, "n": self.n, "points": self.points,
                "reliable": not self.problems(), "problems": self.problems(),
                "undefined": dict(self.undefined or {}),
                "ranges": {k: list(v) for k, v in self.ranges.items()},
                "indices": {o: {p: {"S1": float(self.S1[o][i]), "S1_conf": float(self.S1_conf[o][i]),
                                    "ST": float(self.ST[o][i]), "ST_conf": float(self.ST_conf[o][i])}
                                for i, p in enumerate(self.names)} for o in self.outputs}}

    def table(self) -> str:
        """The indices as a text table, with the problems of the sample if any."""
        lines = [f"Sobol' indices from {self.points} simulations (N = {self.n}), 95 % intervals",
                 f"{'output':<16} {'parameter':<14} {'first order S1':>18} {'total ST':>18}"]
        for o in self.outputs:
            for i, p in enumerate(self.names):
                lines.append(f"{o:<16} {p:<14} {self.S1[o][i]:>9.3f} ± {self.S1_conf[o][i]:<6.3f}"
                             f" {self.ST[o][i]:>9.3f} ± {self.ST_conf[o][i]:<6.3f}")
        for o, why in (self.undefined or {}).items():
            lines.append(f"{o}: no indices ({why})")
        if self.problems():
            lines.append(self.warning())
        return "\n".join(lines)

    def warning(self) -> str:
        """One line saying the sample is too small, and how large to make it."""
        found = self.problems()
        return (f"the sample (N = {self.n}) is too small for these indices to mean anything "
                f"({found[0]}{f', and {len(found) - 1} more' if len(found) > 1 else ''}); "
                f"run again with a larger N, e.g. --n {max(self.n * 4, MIN_N)}")

    def plot(self, path: str | os.PathLike | None = None) -> Figure:
        """The indices as bars with their 95 % intervals, one panel per output.

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
        fig, axes = plt.subplots(1, len(self.outputs), figsize=(4.2 * len(self.outputs), 3.8),
                                 sharey=True, squeeze=False)
        x = np.arange(len(self.names))
        for ax, o in zip(axes[0], self.outputs):
            ax.bar(x - 0.18, self.S1[o], 0.36, yerr=self.S1_conf[o], capsize=3, label="first order S1")
            ax.bar(x + 0.18, self.ST[o], 0.36, yerr=self.ST_conf[o], capsize=3, label="total ST")
            ax.set_xticks(x, [n + (" (log)" if len(self.ranges[n]) > 2 and self.ranges[n][2] else "")
                              for n in self.names], rotation=20, fontsize=8)
            ax.set_title(o, fontsize=10)
            ax.grid(True, axis="y", alpha=0.3)
            ax.set_ylim(0, 1.1)
        axes[0][0].set_ylabel("Sobol' index")
        axes[0][0].legend(fontsize=8)
        fig.suptitle(f"Sensitivity from {self.points} simulations", fontsize=10)
        fig.tight_layout()
        if path is not None:
            from .fitting.reports import save_figure
            save_figure(fig, path)
        return fig


def sensitivity(rig: Component | DAE | str, ranges: Mapping[str, tuple], *, n: int = 4096,
                outputs: Sequence[str] = OUTPUTS, params: Mapping[str, float] | None = None,
                backend: str = "auto", client: Client | None = None, seed: int = 0,
                t_end: float = 0.02, workers: int | None = None,
                progress: bool | Callable[[int, int], object] | None = None,
                out: str | os.PathLike | None = None, overwrite: bool = False) -> Sensitivity:
    """Global sensitivity: Sobol' first-order and total indices (Saltelli's
    sampling scheme, SALib) of summary values with respect to parameters
    varied over ranges, from N (D + 2) simulations of the rig run as one
    sweep (D parameters). Needs pdbfs's extra ``[sensitivity]``.

    A point whose pulse outlasts ``t_end`` is run again over 20 horizons; an
    output undefined at some point gets no indices (a warning says why), and
    a sample too small for its indices to mean anything warns
    (SampleTooSmallWarning) with the N to ask for.

    Parameters
    ----------
    rig : Component, DAE or str
        The rig, its compiled DAE, or a name of ``pdbfs.models.RIGS``.
    ranges : mapping of str to tuple
        ``{parameter: (lo, hi)}``, SI units, or ``(lo, hi, "log")``: sampled
        uniformly in the logarithm (the indices then refer to the logarithm
        of the parameter).
    n : int
        The base sample size N, a power of 2.
    outputs : sequence of str
        The summary keys analysed, each once.
    params : mapping of str to float, optional
        Parameter values, SI units, fixed for every point.
    backend : {"auto", "c", "casadi"}
        As in ``simulate``.
    client : dask.distributed.Client, optional
        Run the sweep on its cluster.
    seed : int
        The seed of the sample and of the bootstrap intervals.
    t_end : float
        End time of each run, s.
    workers : int, optional
        Threads or processes on this machine, as in ``sweep``.
    progress : bool or callable, optional
        As in ``sweep``.
    out : str or os.PathLike, optional
        A folder to stream the sweep to (resumable), as in ``sweep``.
    overwrite : bool
        Replace a folder ``out`` that holds another sweep.

    Returns
    -------
    Sensitivity
        The indices and their 95 % intervals, by output and parameter.

    Raises
    ------
    pdbfs.ParameterError
        For no range, a bad range, N not a power of 2, an output the rig's
        summary does not have: before any run.
    pdbfs.PdbfsError
        When no output is defined at every point.
    pdbfs.errors.MissingExtraError
        Without SALib.

    Examples
    --------
    The peak pressure of the paper's rig depends on the impact speed, hardly
    on the seal's friction:

    >>> import pdbfs
    >>> from pdbfs.models import paper_rig
    >>> s = pdbfs.sensitivity(paper_rig(), {"hammer.v0": (2.0, 3.5), "seal.c": (1e4, 4e4)},
    ...                       n=1024, outputs=["peak_pressure"])
    >>> s.points, [f"{st:.2f}" for st in s.ST["peak_pressure"]]
    (4096, ['0.99', '0.01'])
    >>> s.problems()
    []
    """
    require_extra("sensitivity", "pdbfs.sensitivity (Sobol' indices)")
    from SALib.analyze import sobol as analyze
    from SALib.sample import sobol as sample
    ranges = mapping(ranges, "ranges", "'hammer.v0': (1.5, 5.5)")
    params = mapping(params, "params")
    real(t_end, "t_end")
    if not ranges:
        raise ParameterError("sensitivity: give at least one range, e.g. --range hammer.v0=1.5:5.5")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n <= 0:
        raise ParameterError(f"sensitivity: N = {plain(n)} must be a whole number > 0")
    if n & (n - 1):
        raise ParameterError(f"sensitivity: N = {n} must be a power of 2 (Sobol' sequence), "
                             f"e.g. {1 << int(np.ceil(np.log2(n)))}")
    ranges = {k: _check_range(k, v) for k, v in ranges.items()}
    names = list(ranges)
    rig, outputs = _check_outputs(rig, outputs)
    require(table_bytes(n * (len(names) + 2), 3 * len(names) + 12),
            f"sensitivity: {n * (len(names) + 2)} points", "ask for a smaller N (--n)")
    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    U = sample.sample(problem, int(n), calc_second_order=False, seed=seed)
    X = np.column_stack([np.exp(np.log(lo) + U[:, j] * np.log(hi / lo)) if log else lo + U[:, j] * (hi - lo)
                         for j, (lo, hi, log) in enumerate(ranges.values())])
    pts = Points(names, X, {"kind": "saltelli", "n": int(n), "seed": seed,
                            "ranges": {k: list(v) for k, v in ranges.items()}})
    res = sweep(rig, pts, t_end=t_end, n_out=int(round(t_end / 1e-5)) + 1, params=params,
                backend=backend, client=client, workers=workers, progress=progress, out=out,
                overwrite=overwrite)
    Y = {o: np.array(res.values(o), dtype=float) for o in outputs}
    errors = np.array(res.frame["error"].to_numpy(), dtype=object)
    # pulses outlasting the horizon: followed (run again over FOLLOW horizons) until they end
    late = np.flatnonzero(np.any([~np.isfinite(y) for y in Y.values()], axis=0)
                          & np.array([not e for e in errors]))
    if late.size:
        longer = FOLLOW * t_end
        again = sweep(rig, Points(names, X[late], {"kind": "followed", "t_end": longer}),
                      t_end=longer, n_out=int(round(longer / 1e-5)) + 1, params=params,
                      backend=backend, client=client, workers=workers, progress=progress)
        for o in outputs:
            Y[o][late] = again.values(o)
        errors[late] = again.frame["error"].to_numpy()
    S1, S1c, ST, STc, undefined = {}, {}, {}, {}, {}
    for o in outputs:
        bad = np.flatnonzero(~np.isfinite(Y[o]))
        if bad.size:
            why = errors[bad[0]] or (f"{o} is undefined there" + (
                f" (no pulse, or a pulse still running after {FOLLOW * t_end:.3g} s)"
                if bad[0] in late
                else ""))
            undefined[o] = (f"undefined at {bad.size} of {len(X)} points, first "
                            f"{plain(dict(zip(names, X[bad[0]])))}: {why}")
            continue
        Si = analyze.analyze(problem, Y[o], calc_second_order=False, seed=seed)
        S1[o], S1c[o], ST[o], STc[o] = Si["S1"], Si["S1_conf"], Si["ST"], Si["ST_conf"]
    if not S1:
        why = "; ".join(f"{o}: {w}" for o, w in undefined.items())
        raise PdbfsError(f"sensitivity: no output is defined at every point ({why}); narrow "
                         "the ranges")
    result = Sensitivity(names, [o for o in outputs if o in S1], S1, S1c, ST, STc, int(n),
                         len(X), ranges, undefined)
    for o, why in undefined.items():
        warnings.warn(f"sensitivity: no indices of {o}: {why}", PdbfsWarning, stacklevel=2)
    if result.problems():
        warnings.warn(result.warning(), SampleTooSmallWarning, stacklevel=2)
    return result


def _check_outputs(rig, outputs):
    """(the rig, the outputs as a list), before any run: each output a
    summary value of the rig, named once."""
    from pdbfs.simulation import Simulator
    from pdbfs.simulation.results.summary import keys_for
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        rig = RIGS[rig]()
    outputs = name_list(outputs, "outputs", "'peak_pressure'", distinct=False)  # (named twice: below)
    if not outputs:
        raise ParameterError("sensitivity: no outputs; name at least one summary value, e.g. "
                             "peak_pressure")
    dae = Simulator.of(rig).dae
    keys = keys_for(dae)
    for o in outputs:
        if outputs.count(o) > 1:
            raise ParameterError(f"sensitivity: output {o!r} is named twice")
        if o not in keys:
            raise ParameterError(f"sensitivity: rig {dae.name} has no summary value {o!r}; "
                                 f"it has {', '.join(keys)}")
    return rig, outputs
