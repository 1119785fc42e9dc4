"""Result of one simulation: time and every named variable as numpy arrays.

Values between output points, peaks and level crossings are computed from
the solution itself (a short integration from the nearest output point), so
they do not depend on the output grid.
"""
from __future__ import annotations

import csv
import warnings
from functools import cached_property

import numpy as np

from pdbfs.errors import PdbfsError
from pdbfs.files import whole

from .c_summary import summary_of
from .hermite import Curves
from .initialize import InitialState
from .settings import name_list
from .summary import summarize


#: rows of a CSV formatted at a time (Result.to_csv)
CSV_ROWS = 20000


class Result:
    def __init__(self, sim, t, p, X, Z, settings, stats=None, fast_summary=None, initial=None,
                 states=None, own_stats=False, shared=False, impulse=None):
        self._sim = sim
        self._fast = fast_summary   # the compiled run's own summary (c_summary.py), if any
        self._impulse = impulse     # the contact force's impulse on t, if integrated (summary)
        #: solver statistics of the run: steps, rhs_evals, jac_evals, root_events,
        #: method, wall_time (s), backend (``own_stats``: a dict made for this Result)
        self.stats = stats if own_stats else dict(stats or {})
        if shared:    # a replay's t and p: its plan's, read-only, copied when first read
            self._shared = (t, p)
        else:
            self.t, self.p = t, p
        self._Y = None        # all outputs, computed on first need
        self._rows = {}       # single outputs computed so far
        # the states on the grid; None: ``states()`` makes them when first read
        # (a compiled run's dense output: a summary alone does not need them)
        self._states, self._make_states = X, states
        self._Z = Z
        self.settings = settings
        dae = sim.dae
        names = dae.__dict__.get("_result_names")     # the same for every Result of the rig
        if names is None:
            names = dae.__dict__["_result_names"] = (
                {n: i for i, n in enumerate(dae.y_names)}, {v.name: v.unit for v in dae.y_info},
                {v.name: v.description for v in dae.y_info}, tuple(dae.y_names),
                tuple(dae.p_names), tuple(dae.x_names))
        self._names = names
        self._index = names[0]
        # the start the run began from: an initialize.InitialState, or the start
        # vector of a rig that starts as declared (its record made on first use)
        self._initial = initial

    @property
    def _X(self) -> np.ndarray:
        if self._states is None:         # (made once: a second thread gets the same array)
            self._states = self._make_states()
        return self._states

    # made on first use: most runs (sweeps, a summary) never read them
    @cached_property
    def t(self) -> np.ndarray:
        """The output times (s)."""
        return self._shared[0].copy()

    @cached_property
    def p(self) -> np.ndarray:
        """The parameter vector of the run (the DAE's order)."""
        return self._shared[1].copy()

    @cached_property
    def names(self) -> list:
        """Every variable's name, in the DAE's order."""
        return list(self._names[3])

    @cached_property
    def units(self) -> dict:
        """name -> SI unit."""
        return dict(self._names[1])

    @cached_property
    def descriptions(self) -> dict:
        return dict(self._names[2])

    @cached_property
    def params(self) -> dict:
        """The run's parameter values by name."""
        return dict(zip(self._names[4], self.p.tolist()))

    @property
    def initial(self):
        """The start the run began from (initialize.InitialState): each state's
        value, and what initialization solved (nothing where the rig starts as
        declared)."""
        if isinstance(self._initial, np.ndarray):
            self._initial = InitialState(dict(zip(self._names[5], self._initial.tolist())))
        return self._initial

    @initial.setter
    def initial(self, value):
        self._initial = value

    @property
    def rig(self) -> str:
        return self._sim.dae.name

    def __getitem__(self, name: str) -> np.ndarray:
        if name == "time":
            return self.t
        try:
            i = self._index[name]
        except KeyError:
            import difflib
            close = difflib.get_close_matches(name, self.names, n=3)
            raise KeyError(f"{name!r} is not a variable of rig {self.rig}"
                           + (f"; did you mean {', '.join(close)}?" if close else "")) from None
        if self._Y is not None:
            return self._Y[i]
        if i not in self._rows:
            self._rows[i] = self._sim.outputs(self.t, self._X, self._Z, self.p, [i])[0]
        return self._rows[i]

    def prefetch(self, names):
        """Compute the outputs ``names``, their rates and the event indicators
        in one pass over the grid (a summary reads all of them)."""
        names = [n for n in dict.fromkeys(names) if n in self._index]
        if not names or self._Y is not None:
            return
        Y, rates, E = self._sim.rows_rates_events(self.t, self._X, self._Z, self.p, names)
        curves = self.curves
        for k, n in enumerate(names):
            self._rows[self._index[n]] = Y[k]
            if rates is not None:
                curves._rates[n] = rates[k]
        if curves._kinks is None:
            curves.set_events(E)

    def _all(self):
        if self._Y is None:
            self._Y = self._sim.outputs(self.t, self._X, self._Z, self.p)
        return self._Y

    def __contains__(self, name):
        return name == "time" or name in self._index

    # -- values off the grid ----------------------------------------------------
    def _state_at(self, t: float):
        k = int(np.searchsorted(self.t, t, side="right") - 1)
        k = min(max(k, 0), len(self.t) - 1)
        t0 = self.t[k]
        if t - t0 <= 0:
            return self._X[:, k], self._Z[:, k]
        s = self.settings
        return self._sim.step(self._X[:, k], self.p, t0, t - t0, s["rtol"], s["atol"],
                              s["method"], s["max_step"], backend=s.get("backend", "casadi"))

    def value_at(self, name: str, t: float) -> float:
        """Variable ``name`` at time ``t``, exact to the solver tolerance."""
        i = self._index[name]
        k = int(np.searchsorted(self.t, t))
        if k < len(self.t) and self.t[k] == t and (self._Y is not None or i in self._rows):
            return float(self[name][k])        # an output time whose row is at hand
        x, z = self._state_at(t)
        out = self._sim.dae.function("out")
        at = getattr(self._sim, "p_at", None)        # a run with inputs: theirs at t
        return float(out(t, x, z, self.p if at is None else at(self.p, t))[i])

    @property
    def curves(self):
        """The Hermite interpolants of the variables (pdbfs.simulation.hermite)."""
        if "_curves" not in self.__dict__:
            self._curves = Curves(self)
        return self._curves

    def peak(self, name: str, sign: float = 1.0, window=None) -> tuple[float, float]:
        """(time, value) of the maximum (``sign=-1``: minimum) of ``name``,
        over the run or between the times ``window = (a, b)``: the largest
        sample, refined on the solution between its neighbours (on the
        Hermite interpolant where it is trusted, else by minimising the
        solution itself)."""
        y = sign * self[name]
        k0, k1 = 0, len(y) - 1
        if window is not None:
            k0 = int(np.searchsorted(self.t, window[0]))
            k1 = int(np.searchsorted(self.t, window[1], side="right")) - 1
        k = int(k0 + np.argmax(y[k0:k1 + 1]))
        # on the interpolant of the window's own intervals (at its ends too: a
        # pulse still rising at t_end has its highest value so far there)
        fast = self.curves.peak(name, k, sign, k0, k1) if k0 < k1 else None
        if fast is not None:
            return fast
        from scipy.optimize import minimize_scalar   # the rare case off the interpolant
        a, b = self.t[max(k - 1, 0)], self.t[min(k + 1, len(self.t) - 1)]
        if b <= a:
            return float(self.t[k]), float(self[name][k])
        f = lambda tt: -sign * self.value_at(name, tt)
        r = minimize_scalar(f, bounds=(a, b), method="bounded",
                            options={"xatol": 1e-12 * max(1.0, self.t[-1])})
        if -r.fun >= y[k]:
            return float(r.x), float(-r.fun * sign)
        return float(self.t[k]), float(self[name][k])

    def crossings(self, name: str, level: float = 0.0) -> np.ndarray:
        """Times at which ``name`` crosses ``level``, on the Hermite
        interpolant where it is trusted, else by root finding on the solution."""
        y = self[name] - level
        s = np.sign(y)
        idx = np.flatnonzero(s[:-1] * s[1:] < 0)
        g = lambda tt: self.value_at(name, tt) - level   # noqa: E731
        out = []
        if idx.size:
            from scipy.optimize import brentq
        for k in idx:
            tc = self.curves.crossing(name, level, k)
            out.append(tc if tc is not None else
                       brentq(g, self.t[k], self.t[k + 1], xtol=1e-14, rtol=1e-12))
        return np.array(out)

    # -- export -------------------------------------------------------------------
    def as_dict(self, names=None) -> dict:
        names = self.names if names is None else name_list(names, "names", distinct=False)
        return {"time": self.t, **{n: self[n] for n in names}}

    def to_csv(self, path, names=None, progress=None):
        """Write time and the variables (all by default) as CSV, SI units in
        the header (``name [unit]``). Written CSV_ROWS rows at a time (the
        outputs computed for those rows only, unless the Result holds them):
        the memory it takes does not grow with the run. ``progress``: a
        function called with (rows written, rows in all) after each block."""
        names = self.names if names is None else name_list(names, "names", distinct=False)
        for n in names:
            if n not in self:
                self[n]                                  # its KeyError, with suggestions
        idx = [self._index.get(n) for n in names]
        n_rows = len(self.t)
        # few names, or outputs at hand: whole rows (kept on the Result, as before)
        held = self._Y is not None or len(names) <= 8 or None in idx or \
            all(i in self._rows for i in idx)
        row = ",".join(["%r"] * (len(names) + 1))     # what csv.writer writes, a third sooner
        with whole(path) as part, open(part, "w", newline="") as fh:
            csv.writer(fh).writerow(["time [s]"] + [f"{n} [{self.units[n]}]" for n in names])
            for a in range(0, n_rows, CSV_ROWS):
                b = min(n_rows, a + CSV_ROWS)
                cols = [self[n][a:b] for n in names] if held else \
                    self._sim.outputs(self.t[a:b], self._X[:, a:b], self._Z[:, a:b], self.p, idx)
                data = np.vstack([self.t[a:b], *cols]).T
                if not np.all(np.isfinite(data)):
                    raise PdbfsError("refusing to write NaN or infinite values to " + str(path))
                fh.write("".join([row % tuple(r) + "\r\n" for r in data.tolist()]))
                if progress is not None:
                    progress(b, n_rows)
        return path

    def to_pandas(self, names=None):
        """A pandas DataFrame indexed by time (needs pandas installed)."""
        try:
            import pandas as pd
        except ImportError:
            raise PdbfsError("to_pandas() needs pandas: pip install pandas") from None
        d = self.as_dict(names)
        t = d.pop("time")
        return pd.DataFrame(d, index=pd.Index(t, name="time"))

    def plot(self, names=None, path=None, title=None):
        """Plot variables against time in ms (one panel per unit); save to
        ``path`` if given. Returns the matplotlib Figure."""
        from .plotting import plot_result
        return plot_result(self, names, path, title)

    def summary(self) -> dict:
        """Peak pressure, time of peak, pulse duration, ..., and whether the
        pulse ended inside the run (``complete``): located on the summary's
        own solution, the same whatever the output grid (see summary.py).
        Warns (PulseIncompleteWarning) when the pulse outlasts the run.
        Computed once per Result."""
        if "_summary" not in self.__dict__ and self._fast is not None:
            d = summary_of(self._sim.dae, self._fast)
            if d is not None:                  # the run's own: nothing integrated again
                self._summary, self._summary_warnings = d, []
        if "_summary" not in self.__dict__:    # its warnings are kept and given again each call
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                self._summary = summarize(self)
            self._summary_warnings = caught
        for w in self._summary_warnings:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return dict(self._summary)
