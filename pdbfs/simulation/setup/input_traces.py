"""The inputs of one run (``simulate(..., inputs={"command": (t, u)})``):
each input's values checked and made a piecewise-linear trace, and the
segments a run is integrated over.

An input is given as

* a trace ``(t, u)``: values at times, interpolated linearly; a time given
  twice is a jump (the value after it holds from that time on). Its times
  are breakpoints: the solver stops and restarts at each (time events), so
  a kink or a jump lands exactly, between output points too. The trace must
  cover the run, [0, t_end]: a run does not guess values;
* a number: held for the whole run;
* a function of time, ``f(t) -> value`` (input_function.py: sampled into
  a trace that agrees with it to CALLABLE_RTOL of its largest value at the
  middle of every interval);

an input not given holds its ``start`` value. The summary follows a pulse
past t_end only as far as the traces go (driven.Driven.known_until). Over
each segment between two breakpoints (of all inputs together) every input
is u + du (t - t_ref): the DAE's input entries of p
(pdbfs.modelling.rig_inputs) for that segment are ``Drive.p_at``'s; on an
output grid, ``Drive.P_on`` gives each point its own (right-continuous: at
a breakpoint, the segment that starts there).
"""
from __future__ import annotations

import numbers

import numpy as np

from pdbfs.errors import ParameterError, plain

from .input_function import sample_callable

#: a trace ending this close (relative to the run) before t_end covers it
END_SLACK = 1e-9
#: breakpoints this close (relative) to an output point are moved onto it
SNAP = 64 * np.finfo(float).eps


def drive_of(dae, inputs, grid):
    """The Drive of ``inputs`` (a dict {input name: trace, number or
    function}) for a run on ``grid``, every value checked (one ParameterError
    naming the input and what is wrong); None when no input is given."""
    if inputs is None:
        return None
    if not isinstance(inputs, dict):
        raise ParameterError(f"inputs = {' '.join(plain(inputs).split())[:80]}: give a dict of "
                             "input name -> trace (t, u), number or function of time")
    if not inputs:
        return None
    names = dae.input_names
    for name in inputs:
        if not isinstance(name, str) or name not in names:
            if not names:
                raise ParameterError(f"inputs: rig {dae.name} has no inputs (an Input component "
                                     f"declares one), so {plain(name)} cannot be given")
            import difflib
            close = difflib.get_close_matches(str(name), names, n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise ParameterError(f"inputs: {plain(name)} is not an input of rig {dae.name} "
                                 f"(its inputs: {', '.join(names)}){hint}")
    t0, t1 = float(grid[0]), float(grid[-1])
    traces = []
    for info in dae.inputs:
        given = inputs.get(info.name, info.start)
        traces.append(trace_of(info.name, given, t0, t1, grid))
    return Drive(dae, traces, {n: v for n, v in inputs.items()})


def trace_of(name, given, t0, t1, grid):
    """(t, u) of one input, checked: a held value is one sample."""
    if isinstance(given, numbers.Real) and not isinstance(given, (bool, np.bool_)):
        v = float(given)
        if not np.isfinite(v):
            raise ParameterError(f"inputs: {name} = {v}: must be finite")
        return np.array([t0]), np.array([v])
    if callable(given):
        return sample_callable(name, given, grid)
    arr = None
    if isinstance(given, (tuple, list)) and len(given) == 2:
        arr = given
    elif hasattr(given, "__array__") and np.ndim(given) == 2 and np.shape(given)[1] == 2:
        table = np.asarray(given)             # two columns (a numpy array, a DataFrame)
        arr = (table[:, 0], table[:, 1])
    if arr is None:
        shown = f"an array of shape {given.shape}" if isinstance(given, np.ndarray) else \
            " ".join(plain(given).split())[:60]
        raise ParameterError(f"inputs: {name} = {shown}: give a trace (t, u) of times and "
                             "values, a number, or a function of time")
    try:
        t = np.asarray(arr[0], dtype=float)
        u = np.asarray(arr[1], dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"inputs: {name}: the trace's times and values must be numbers") \
            from None
    if t.ndim != 1 or u.ndim != 1:
        raise ParameterError(f"inputs: {name}: the trace (t, u) takes two lists of numbers, "
                             f"not arrays of shapes {t.shape} and {u.shape}")
    return check_trace(name, t, u, t0, t1)


def check_trace(name, t, u, t0, t1):
    """The trace's rules: equal lengths, two samples at least, finite,
    times not decreasing (two at one time: a jump; three: refused), the run
    covered."""
    if t.size != u.size:
        raise ParameterError(f"inputs: {name}: {t.size} times but {u.size} values")
    if t.size < 2:
        raise ParameterError(f"inputs: {name}: a trace needs two samples at least (a number "
                             "holds one value)")
    for arr, what in ((t, "time"), (u, "value")):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            k = int(bad[0])
            at = f" at t = {t[k]:.6g} s" if what == "value" and np.isfinite(t[k]) else ""
            raise ParameterError(f"inputs: {name}: {what} {k + 1} is {arr[k]}{at}; every time "
                                 "and value must be finite")
    d = np.diff(t)
    if np.any(d < 0):
        k = int(np.argmax(d < 0)) + 1
        raise ParameterError(f"inputs: {name}: the times must not decrease: {t[k]:.6g} s "
                             f"(sample {k + 1}) after {t[k - 1]:.6g} s")
    if d.size > 1 and np.any((d[:-1] == 0) & (d[1:] == 0)):
        k = int(np.argmax((d[:-1] == 0) & (d[1:] == 0)))
        raise ParameterError(f"inputs: {name}: three samples at t = {t[k]:.6g} s; a jump is "
                             "two samples at one time (before and after)")
    slack = END_SLACK * max(abs(t1 - t0), abs(t1), 1e-300)
    if t[0] > t0 + slack or t[-1] < t1 - slack:
        raise ParameterError(f"inputs: {name}: the trace covers {t[0]:.6g} .. {t[-1]:.6g} s, the "
                             f"run {t0:.6g} .. {t1:.6g} s; give values over the whole run")
    return t, u


class Drive:
    """The inputs of a run: one trace per input of the rig (in ``dae.inputs``
    order; a held one is a single sample), and the DAE's rows of their
    values, slopes and t_ref in p."""

    def __init__(self, dae, traces, given=None):
        self.names = dae.input_names
        self.traces = traces
        self.given = given or {}        # what the caller gave, by name (a Result keeps it)
        self.u0, self.du0, self.t_ref = dae.input_rows()
        edges = [t for t, _ in traces if t.size > 1]
        self.edges = np.unique(np.concatenate(edges)) if edges else np.zeros(0)

    def coefficients(self, t_ref, t_mid):
        """(values at ``t_ref``, slopes), each (inputs x len(t_mid)), of the
        trace pieces holding the times ``t_mid`` (arrays of equal length);
        before a trace's first time or after its last the input is held."""
        t_ref = np.atleast_1d(np.asarray(t_ref, float))
        t_mid = np.atleast_1d(np.asarray(t_mid, float))
        A = np.empty((len(self.traces), t_mid.size))
        B = np.zeros_like(A)
        for i, (t, u) in enumerate(self.traces):
            if t.size == 1:
                A[i] = u[0]
                continue
            k = np.searchsorted(t, t_mid, side="right") - 1
            inside = (k >= 0) & (k < t.size - 1)
            kk = np.clip(k, 0, t.size - 2)
            slope = np.where(inside, (u[kk + 1] - u[kk]) / np.where(inside, t[kk + 1] - t[kk], 1.0),
                             0.0)
            held = np.where(k < 0, u[0], u[-1])
            A[i] = np.where(inside, u[kk] + slope * (t_ref - t[kk]), held)
            B[i] = slope
        return A, B

    def p_at(self, p, a, c=None) -> np.ndarray:
        """``p`` with the inputs of the segment [a, c] (every input linear
        on it), t_ref = a; without ``c``, of the segment starting at a."""
        mid = a if c is None else 0.5 * (a + c)
        A, B = self.coefficients([a], [mid])
        q = np.array(p, dtype=float, copy=True)
        q[self.u0:self.du0], q[self.du0:self.t_ref], q[self.t_ref] = A[:, 0], B[:, 0], a
        return q

    def P_on(self, p, grid) -> np.ndarray:
        """One column of p per time of ``grid``: the inputs at that time (the
        segment starting there at a breakpoint), t_ref the time itself."""
        grid = np.asarray(grid, float).ravel()
        P = np.repeat(np.asarray(p, float).reshape(-1, 1), grid.size, axis=1)
        A, B = self.coefficients(grid, grid)
        P[self.u0:self.du0], P[self.du0:self.t_ref], P[self.t_ref] = A, B, grid
        return P

    def pieces(self, grid):
        """[(a, c, sub)]: the segments of [grid[0], grid[-1]] between the
        breakpoints (those within SNAP of an output point moved onto it), each
        with the output points inside it and its ends (``sub``)."""
        grid = np.asarray(grid, float)
        t0, t1 = float(grid[0]), float(grid[-1])
        tol = SNAP * max(abs(t0), abs(t1))
        b = self.edges[(self.edges > t0 + tol) & (self.edges < t1 - tol)]
        if b.size and grid.size > 2:
            k = np.clip(np.searchsorted(grid, b), 1, grid.size - 1)
            near = np.where(np.abs(grid[k] - b) <= np.abs(grid[k - 1] - b), grid[k], grid[k - 1])
            b = np.unique(np.where(np.abs(near - b) <= tol, near, b))
            b = b[(b > t0) & (b < t1)]
        if b.size > 1:            # breakpoints closer than a solver can step: one is enough
            b = b[np.concatenate([[True], np.diff(b) > tol])]
            b = b[(b - t0 > tol) & (t1 - b > tol)]
        edges = np.concatenate([[t0], b, [t1]])
        return [(a, c, np.concatenate([[a], grid[(grid > a) & (grid < c)], [c]]))
                for a, c in zip(edges[:-1], edges[1:])]

    def kink_row(self, grid) -> np.ndarray:
        """A row that changes sign on every output interval holding a
        breakpoint (at its ends included): an event indicator for the
        Hermite curves (hermite.py), whose cubics must not span a kink."""
        grid = np.asarray(grid, float).ravel()
        if grid.size < 2:
            return np.ones(grid.size)
        lo = np.searchsorted(self.edges, grid[:-1], side="left")
        hi = np.searchsorted(self.edges, grid[1:], side="right")
        flip = hi > lo                                   # a breakpoint in [t_i, t_i+1]
        return np.concatenate([[1.0], np.where(np.cumsum(flip) % 2, -1.0, 1.0)])


def refuse_differentiated(dae, names):
    """Linearization in an input the rig differentiates (its slope enters
    the equations: a prescribed position whose velocity a damper needs) would
    leave out the term in its derivative: refused, naming it."""
    rows = dae.input_rows()
    if rows is None:
        return
    import casadi as ca
    # at t = t_ref the inputs' values are u; a slope left there is a derivative used
    eqs = ca.substitute(ca.vertcat(dae.ode, dae.alg, dae.y), dae.t, dae.p[rows[2]])
    for name in names:
        if name in dae.input_names:
            k = dae.input_names.index(name)
            if ca.depends_on(eqs, dae.p[rows[1] + k]):
                raise ParameterError(
                    f"linearize: input {name} is differentiated by rig {dae.name} (its rate "
                    "enters the equations, as a prescribed position's velocity does), so B and D "
                    "would miss the term in its derivative; linearize in a force or pressure "
                    "input, or filter the input before it prescribes a position")
