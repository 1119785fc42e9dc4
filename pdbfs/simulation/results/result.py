"""Result of one simulation: time and every named variable as numpy arrays,
with values, peaks and crossings located on the solution itself."""
from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from ..setup.initialize import InitialState
from .c_summary import summary_of
from .exports import ResultExports
from .hermite import Curves
from .summary import implausible, summarize

if TYPE_CHECKING:
    from .source import RunSource


class Result(ResultExports):
    """One simulation of a rig: time and every variable as numpy arrays, SI units.

    ``res["oil.pressure"]`` is a variable on the output grid (``res["time"]`` is
    ``res.t``; an unknown name is a KeyError naming the closest). Values off the grid,
    peaks and crossings are located on the solution itself: ``value_at()``, ``peak()``,
    ``crossings()``, ``summary()``; exports: ``to_csv()``, ``to_pandas()``,
    ``as_dict()``, ``plot()``. Made by ``simulate``.

    Attributes
    ----------
    t : numpy.ndarray
        The output times, s.
    names, units, descriptions : list and dicts
        Every variable's dotted name (the DAE's order); unit and description by name.
    params, p : dict and numpy.ndarray
        The run's parameter values (SI units) by name, and as a vector in the DAE's order.
    initial : InitialState
        The start the run began from, and what initialization solved.
    final : dict
        The states at the last output time by name (a next run's ``start``).
    rig : str
        The rig's name.
    settings, stats : dict
        The settings as used (rtol, atol, method, ...) and the solver's statistics (steps, ...).

    Examples
    --------
    >>> from pdbfs.models import paper_rig
    >>> res = paper_rig().simulate(0.02)
    >>> res["oil.pressure"].shape, res.units["oil.pressure"], "oil.pressure" in res
    ((2001,), 'Pa', True)
    >>> res.to_pandas(["oil.pressure", "hammer.v"]).shape
    (2001, 2)
    """

    def __init__(self, sim: RunSource, t: np.ndarray, p: np.ndarray, X: np.ndarray | None, Z: np.ndarray,
                 settings: dict, stats: dict | None = None, fast_summary: tuple | None = None,
                 initial: InitialState | np.ndarray | None = None, states: Callable | None = None,
                 own_stats: bool = False, impulse: np.ndarray | None = None):
        self._sim = sim
        self._fast = fast_summary   # the compiled run's own summary (c_summary.py), if any
        self._impulse = impulse     # the contact force's impulse on t, if integrated (summary)
        #: solver statistics of the run: steps, rhs_evals, jac_evals, root_events,
        #: method, wall_time (s), backend (``own_stats``: a dict made for this Result)
        self.stats = stats if own_stats else dict(stats or {})
        self._shared = (t, p)     # the run's (a kept grid: read-only), copied when first read
        self._Y = None        # all outputs, computed on first need
        self._rows = {}       # single outputs computed so far
        # the states on the grid; None: ``states()`` makes them when first read
        # (a compiled run's dense output: a summary alone does not need them)
        self._states, self._make_states = X, states
        self._Z = Z
        self.settings = settings
        dae, state = sim.dae, sim.state
        names = state.result_names     # the same for every Result of the rig
        if names is None:
            names = state.result_names = (
                {n: i for i, n in enumerate(dae.y_names)}, {v.name: v.unit for v in dae.y_info},
                {v.name: v.description for v in dae.y_info}, tuple(dae.y_names),
                tuple(dae.p_names), tuple(dae.x_names))
        self._names = names
        self._index = names[0]
        # the start the run began from: an initialize.InitialState, or the start
        # vector of a rig that starts as declared (its record made on first use)
        self._initial = initial

    def detached(self) -> dict:
        """This Result's own data, without its Simulator, to be sent to another
        process (a sweep's worker's); ``Result.attach`` makes it a Result there.

        Returns
        -------
        dict
            The data (a compiled run's states made now; no summary).
        """
        self._X                 # (made once: kept on this Result)
        return {k: v for k, v in vars(self).items()
                if k not in ("_sim", "curves", "_summary", "_summary_warnings", "_make_states")}

    @classmethod
    def attach(cls, sim: RunSource, state: dict) -> "Result":
        """A Result again, from what ``detached`` gave.

        Parameters
        ----------
        sim : RunSource
            The Simulator of the same rig (the parent process's, for a sweep's worker).
        state : dict
            What ``detached`` returned.

        Returns
        -------
        Result
        """
        res = cls.__new__(cls)
        for name, value in {**state, "_sim": sim}.items():
            setattr(res, name, value)
        return res

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
        """name -> description."""
        return dict(self._names[2])

    @cached_property
    def params(self) -> dict:
        """The run's parameter values by name."""
        return dict(zip(self._names[4], self.p.tolist()))

    @property
    def initial(self) -> InitialState:
        """The start the run began from (initialize.InitialState): each state's
        value, and what initialization solved (nothing for a declared start)."""
        if isinstance(self._initial, np.ndarray):
            self._initial = InitialState(dict(zip(self._names[5], self._initial.tolist())))
        return self._initial

    @initial.setter
    def initial(self, value: InitialState):
        self._initial = value

    @property
    def final(self) -> dict:
        """The states at the last output time by name, SI units: where a run
        that goes on from here starts (``start=res.final``)."""
        return dict(zip(self._names[5], self._X[:, -1].tolist()))

    @property
    def rig(self) -> str:
        """The rig's name."""
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

    def prefetch(self, names: str | Sequence[str]) -> None:
        """Compute some outputs, their rates and the event indicators in one pass.

        Parameters
        ----------
        names : str or sequence of str
            The variables (names the rig does not have are left out).
        """
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
        k = min(max(int(np.searchsorted(self.t, t, side="right") - 1), 0), len(self.t) - 1)
        t0 = self.t[k]
        if t - t0 <= 0:
            return self._X[:, k], self._Z[:, k]
        s = self.settings
        return self._sim.step(self._X[:, k], self.p, t0, t - t0, s["rtol"], s["atol"],
                              s["method"], s["max_step"], backend=s.get("backend", "casadi"))

    def value_at(self, name: str, t: float) -> float:
        """A variable at any time of the run, exact to the solver tolerance.

        Parameters
        ----------
        name : str
            The variable's dotted name (``"oil.pressure"``).
        t : float
            The time, s, within the run.

        Returns
        -------
        float
            The value, in the variable's unit (``units[name]``).

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> res = paper_rig().simulate(0.02, n_out=21)
        >>> f"{res.value_at('oil.pressure', 0.005) / 1e6:.3g} MPa"
        '82.2 MPa'
        """
        i = self._index[name]
        k = int(np.searchsorted(self.t, t))
        if k < len(self.t) and self.t[k] == t and (self._Y is not None or i in self._rows):
            return float(self[name][k])        # an output time whose row is at hand
        x, z = self._state_at(t)
        out = self._sim.dae.function("out")
        at = getattr(self._sim, "p_at", None)        # a run with inputs: theirs at t
        return float(out(t, x, z, self.p if at is None else at(self.p, t))[i])

    @cached_property
    def curves(self) -> Curves:
        """The cubic Hermite interpolants of the variables between output points."""
        return Curves(self)

    def peak(self, name: str, sign: float = 1.0, window: tuple[float, float] | None = None
             ) -> tuple[float, float]:
        """The largest (or smallest) value of a variable and when, located on
        the solution: the largest sample, refined between its neighbours.

        Parameters
        ----------
        name : str
            The variable's dotted name.
        sign : float
            1: the maximum; -1: the minimum.
        window : tuple of float, optional
            ``(a, b)``, s: the peak between these times (default: the whole run).

        Returns
        -------
        tuple of float
            (time in s, value in the variable's unit).

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> res = paper_rig().simulate(0.02)
        >>> t, x = res.peak("piston.s")
        >>> f"{x * 1e3:.3g} mm at {t * 1e3:.3g} ms"
        '9.47 mm at 5.57 ms'
        >>> f"{res.peak('hammer.v', sign=-1)[1]:.3g} m/s"
        '-2.52 m/s'
        """
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
        r = minimize_scalar(lambda tt: -sign * self.value_at(name, tt), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-12 * max(1.0, self.t[-1])})
        if -r.fun >= y[k]:
            return float(r.x), float(-r.fun * sign)
        return float(self.t[k]), float(self[name][k])

    def crossings(self, name: str, level: float = 0.0) -> np.ndarray:
        """The times at which a variable crosses a level, located on the solution.

        Parameters
        ----------
        name : str
            The variable's dotted name.
        level : float
            The level, in the variable's unit.

        Returns
        -------
        numpy.ndarray
            The crossing times, s, increasing (empty if it never crosses).

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> res = paper_rig().simulate(0.02)
        >>> [f"{t * 1e3:.3g} ms" for t in res.crossings("hammer.v", 0.0)]
        ['6.29 ms']
        """
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

    def summary(self) -> dict:
        """The pulse's figures, located on the solution whatever the output
        grid, computed once: peak pressure, time of peak, pulse duration,
        peak contact force, maximum piston displacement, restitution, and
        whether the pulse ended inside the run (``complete``): those the
        rig's ``summary_signals`` give roles for (a rig whose hammer strikes
        more than once also lists its blows: ``impact_count``, ...).

        Returns
        -------
        dict
            Figure name -> value, SI units (``SUMMARY_UNITS``); None where
            the run cannot give it (the pulse not over: a PulseIncompleteWarning says so).
            A figure outside its physical range (a restitution above 1, a
            pressure above every source's) warns (ImplausibleResultWarning),
            naming the likely cause.

        Examples
        --------
        >>> from pdbfs.models import paper_rig
        >>> s = paper_rig().simulate(0.02).summary()
        >>> f"{s['peak_pressure'] / 1e6:.3g} MPa, {s['pulse_duration'] * 1e3:.3g} ms"
        '92.1 MPa, 11.9 ms'
        >>> s["complete"]
        True
        """
        if "_summary" not in self.__dict__ and self._fast is not None:
            d = summary_of(self._sim, self._fast)
            if d is not None:                  # the run's own: nothing integrated again
                self._summary, self._summary_warnings = d, implausible(self, d)
        if "_summary" not in self.__dict__:    # its warnings are kept and given again each call
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                self._summary = summarize(self)
            self._summary_warnings = caught + implausible(self, self._summary)
        for w in self._summary_warnings:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return dict(self._summary)
