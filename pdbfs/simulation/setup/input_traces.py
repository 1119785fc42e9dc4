"""The inputs of one run (``simulate(..., inputs={"command": (t, u)})``):
each input's values checked and made a piecewise-linear trace, and the
segments a run is integrated over.

An input is given as

* a trace ``(t, u)`` (its one layout, input_layout.py: times first, or
  named columns): values at times, interpolated linearly; a time given
  twice is a jump (the value after it holds from that time on; refused
  inside the run for an input the rig differentiates: its impulse would
  be lost). Its times
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
(pdbfs.modelling.rig_inputs) for that segment are ``Drive.p_at``'s (of
every segment at once: ``Drive.segments``, arrays, for the compiled run
over all of them in one call); on an output grid, ``Drive.P_on`` gives
each point its own (right-continuous: at a breakpoint, the segment that
starts there).
"""
from __future__ import annotations

import numbers

import numpy as np

from pdbfs.errors import ParameterError, plain

from .input_function import sample_callable
from .input_layout import columns, shown

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
    traces = [input_trace(dae, info.name, inputs.get(info.name, info.start), grid)
              for info in dae.inputs]
    return Drive(dae, traces, {n: v for n, v in inputs.items()})


def input_trace(dae, name, given, grid):
    """(t, u) of the input ``name`` of ``dae`` for a run on ``grid``
    (trace_of), and refused where it jumps inside the run although the rig
    differentiates it (refuse_jump)."""
    t, u = trace_of(name, given, float(grid[0]), float(grid[-1]), grid)
    if t.size > 2:
        refuse_jump(dae, name, t, u, float(grid[0]), float(grid[-1]))
    return t, u


def trace_of(name, given, t0, t1, grid):
    """(t, u) of one input, checked: a held value is one sample. A trace is
    given in one layout (``columns``): the pair (t, u), or named columns."""
    if isinstance(given, numbers.Real) and not isinstance(given, (bool, np.bool_)):
        v = float(given)
        if not np.isfinite(v):
            raise ParameterError(f"inputs: {name} = {v}: must be finite")
        return np.array([t0]), np.array([v])
    if callable(given):
        return sample_callable(name, given, grid)
    t, u = columns(name, given)
    if t.size == 2 and u.size == 2 and not isinstance(given, (dict, tuple)) and \
            not hasattr(given, "columns"):
        # two samples as a list or a 2 x 2 array read as rows (t, u) too
        rows = (np.array([t[0], u[0]]), np.array([t[1], u[1]]))
        if _valid(name, t, u, t0, t1) and _valid(name, *rows, t0, t1) and \
                not (np.array_equal(rows[0], t) and np.array_equal(rows[1], u)):
            raise ParameterError(
                f"inputs: {name} = {shown(given)}: reads both as (t, u) = "
                f"({plain(t.tolist())}, {plain(u.tolist())}) and as rows (t = "
                f"{plain(rows[0].tolist())}, u = {plain(rows[1].tolist())}); give a tuple "
                f"(t, u) or a dict {{'t': [...], '{name}': [...]}}")
    return check_trace(name, t, u, t0, t1)


def _valid(name, t, u, t0, t1) -> bool:
    try:
        check_trace(name, t, u, t0, t1)
    except ParameterError:
        return False
    return True


def refuse_jump(dae, name, t, u, t0, t1) -> None:
    """A trace that jumps inside the run (a time given twice, the values
    differing) of an input the rig differentiates (a position it
    prescribes, whose velocity a damper needs): the jump's impulse would be
    lost (the slope of each segment is all the rig sees), so it is refused.
    A kink is fine: the rate jumps, a damper's force with it, no impulse."""
    d = np.diff(t)
    at = np.flatnonzero((d == 0) & (u[1:] != u[:-1]) & (t[1:] > t0) & (t[1:] < t1))
    if not at.size or name not in differentiated(dae):
        return
    k = int(at[0])
    raise ParameterError(
        f"inputs: {name}: the trace jumps at t = {t[k]:.6g} s (from {u[k]:.6g} to "
        f"{u[k + 1]:.6g}), but rig {dae.name} differentiates this input (a position it "
        "prescribes, whose velocity a damper needs): the jump's impulse would be lost; give "
        "the jump a rise time (two distinct times) or filter the input")


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
        # sorted already: one trace's times (a jump's twice) need no sort, only their repeats out
        self.edges = _distinct(edges[0]) if len(edges) == 1 else \
            np.unique(np.concatenate(edges)) if edges else np.zeros(0)
        self._segments = None           # (the grid, its Segments): the last grid's, see release

    def coefficients(self, t_ref, t_mid):
        """(values at ``t_ref``, slopes), each (inputs x len(t_mid)), of the
        trace pieces holding the times ``t_mid`` (arrays of equal length);
        before a trace's first time or after its last the input is held."""
        t_ref = np.atleast_1d(np.asarray(t_ref, float))
        t_mid = np.atleast_1d(np.asarray(t_mid, float))
        out = np.empty((2 * len(self.traces), t_mid.size))
        self._fill(out, t_ref, t_mid)
        n = len(self.traces)
        return out[:n], out[n:]

    def _fill(self, out, t_ref, t_mid):
        """coefficients' rows written into ``out`` (2 inputs x times, or
        its transpose): one input at a time, so that a long trace's
        intermediate arrays are never there for all inputs at once."""
        n = len(self.traces)
        for i, (t, u) in enumerate(self.traces):
            if t.size == 1:
                out[i], out[n + i] = u[0], 0.0
                continue
            k = np.searchsorted(t, t_mid, side="right") - 1
            inside = (k >= 0) & (k < t.size - 1)
            np.clip(k, 0, t.size - 2, out=k)
            slope = (u[k + 1] - u[k]) / np.where(inside, t[k + 1] - t[k], 1.0)
            slope[~inside] = 0.0
            value = u[k] + slope * (t_ref - t[k])
            outside = ~inside
            value[outside] = np.where(t_mid[outside] < t[0], u[0], u[-1])
            out[i], out[n + i] = value, slope

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

    def segments(self, grid) -> Segments:
        """The segments of [grid[0], grid[-1]] between the breakpoints (those
        within SNAP of an output point moved onto it), as arrays: a few
        numbers per breakpoint, whatever the length of the traces (made
        once per grid)."""
        grid = np.asarray(grid, float)
        kept = self._segments
        if kept is not None and kept[0].shape == grid.shape and np.array_equal(kept[0], grid):
            return kept[1]
        t0, t1 = float(grid[0]), float(grid[-1])
        tol = SNAP * max(abs(t0), abs(t1))
        b = self.edges[np.searchsorted(self.edges, t0 + tol, side="right"):
                       np.searchsorted(self.edges, t1 - tol, side="left")]
        if b.size and grid.size > 2:
            k = np.clip(np.searchsorted(grid, b), 1, grid.size - 1)
            near = np.where(np.abs(grid[k] - b) <= np.abs(grid[k - 1] - b), grid[k], grid[k - 1])
            del k
            b = np.where(np.abs(near - b) <= tol, near, b)
            del near
            b = _distinct(b if np.all(b[1:] >= b[:-1]) else np.sort(b))
            b = b[(b > t0) & (b < t1)]
        if b.size > 1:            # breakpoints closer than a solver can step: one is enough
            b = b[np.concatenate([[True], np.diff(b) > tol])]
            b = b[(b - t0 > tol) & (t1 - b > tol)]
        edges = np.concatenate([[t0], b, [t1]])
        del b
        coef = np.empty((edges.size - 1, 2 * len(self.traces)))
        self._fill(coef.T, edges[:-1], 0.5 * (edges[:-1] + edges[1:]))
        seg = Segments(edges, coef, grid, self)
        self._segments = (grid.copy(), seg)
        return seg

    def release(self) -> None:
        """Forget the segments made last (a run keeps its Drive: a long
        trace's segments are a few times its size)."""
        self._segments = None

    def pieces(self, grid):
        """(a, c, sub) of each segment in turn: its ends and its grid, the
        ends and the output points inside (made one at a time)."""
        grid = np.asarray(grid, float)
        seg = self.segments(grid)
        for k in range(seg.count):
            a, c = seg.edges[k], seg.edges[k + 1]
            yield a, c, np.concatenate([[a], grid[seg.lo[k]:seg.hi[k]], [c]])

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


class Segments:
    """The segments of one run's inputs: ``edges`` (count + 1 times),
    ``coef`` (one row a segment: each input's value at the segment's
    start, then each input's slope; C order, as the compiled run over the
    segments reads them), and the output points strictly inside segment
    k, ``grid[lo[k]:hi[k]]``."""

    def __init__(self, edges, coef, grid, drive):
        self.edges, self.coef, self._grid = edges, coef, grid
        self.rows = (drive.u0, drive.du0, drive.t_ref)
        self.inputs = coef.shape[1] // 2
        self._lo_hi = None

    @property
    def lo(self) -> np.ndarray:
        """The index of the first output point inside each segment."""
        return self._bounds()[0]

    @property
    def hi(self) -> np.ndarray:
        """One past the index of the last output point inside each segment."""
        return self._bounds()[1]

    def _bounds(self):
        # made when asked (a run segment by segment from Python): the compiled
        # run over the segments finds them itself
        if self._lo_hi is None:
            self._lo_hi = (np.searchsorted(self._grid, self.edges[:-1], side="right"),
                           np.searchsorted(self._grid, self.edges[1:], side="left"))
        return self._lo_hi

    @property
    def count(self) -> int:
        """The number of segments."""
        return self.edges.size - 1

    def p_of(self, p, k) -> np.ndarray:
        """``p`` with the inputs of segment k (t_ref its start)."""
        u0, du0, t_ref = self.rows
        q = np.array(p, dtype=float, copy=True)
        q[u0:t_ref], q[t_ref] = self.coef[k], self.edges[k]
        return q


def _distinct(t) -> np.ndarray:
    """A sorted array without its repeats."""
    return t[np.concatenate([[True], t[1:] != t[:-1]])] if t.size else t


def differentiated(dae) -> set:
    """The names of the inputs whose rate enters the equations (the rig
    differentiates them: a prescribed position whose velocity a damper
    needs); made once per DAE and kept with its functions."""
    def make():
        rows = dae.input_rows()
        if rows is None:
            return frozenset()
        import casadi as ca
        # at t = t_ref the inputs' values are u; a slope left there is a derivative used
        eqs = ca.substitute(ca.vertcat(dae.ode, dae.alg, dae.y), dae.t, dae.p[rows[2]])
        return frozenset(n for k, n in enumerate(dae.input_names)
                         if ca.depends_on(eqs, dae.p[rows[1] + k]))
    return dae.cached("differentiated inputs", make)


def refuse_differentiated(dae, names):
    """Linearization in an input the rig differentiates would leave out the
    term in its derivative: refused, naming it."""
    for name in names:
        if name in differentiated(dae):
            raise ParameterError(
                f"linearize: input {name} is differentiated by rig {dae.name} (its rate "
                "enters the equations, as a prescribed position's velocity does), so B and D "
                "would miss the term in its derivative; linearize in a force or pressure "
                "input, or filter the input before it prescribes a position")
