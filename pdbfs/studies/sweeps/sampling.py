"""The points of a sweep: grids and zipped lists, Latin hypercube and Sobol'
samples of ranges (scipy.stats.qmc), Monte Carlo draws from distributions.

A point set is a number of points over named parameters that hands out
blocks of rows (``block(i0, i1)``, an array of i1 - i0 x len(names)) and a
``spec`` that identifies it (the sweep's manifest hashes it to recognise a
sweep it is asked to resume). Nothing holds one Python object per point:
a million-point grid is indexed, not listed. Sobol' and Monte Carlo samples
are drawn block by block (the same points as drawn whole), so their size is
bounded by time, not memory; a Latin hypercube is stratified as a whole and
is drawn whole, refused up front if it cannot fit.
"""
from __future__ import annotations

import math
import threading
import warnings
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from pdbfs.errors import ParameterError, PdbfsWarning, plain
from pdbfs.simulation.setup.memory import require

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

SAMPLERS = ("lhs", "sobol", "mc")
DISTRIBUTIONS = {"normal": 2, "uniform": 2, "lognormal": 2}   # name -> number of arguments
#: bytes per point and parameter while scipy draws a Latin hypercube: the
#: jitter, the permutations, two temporaries and the result kept
LHS_BYTES = 40.0
#: the most points of scipy's Sobol' sequence (30 bits)
SOBOL_MAX = 2 ** 30


class PointSet:
    """The points of a sweep: ``n`` rows of values of the parameters ``names``."""

    names: list[str]
    n: int

    def block(self, i0: int, i1: int) -> np.ndarray:
        """A block of the points, as rows of parameter values.

        Parameters
        ----------
        i0, i1 : int
            The first point and one past the last, 0 <= i0 <= i1 <= n.

        Returns
        -------
        numpy.ndarray
            The points i0 .. i1 - 1: i1 - i0 rows of len(names) values, SI units.
        """
        raise NotImplementedError

    @property
    def spec(self) -> dict:
        """What defines the points, as JSON-ready data (a resumed sweep checks it)."""
        raise NotImplementedError

    def all(self) -> np.ndarray:
        """Every point, as rows."""
        return self.block(0, self.n)


class Grid(PointSet):
    """The points of value lists: every combination (the last name varying
    fastest), or the lists read as columns of equal length. A million-point
    grid is indexed, not listed.

    Parameters
    ----------
    values : dict
        ``{parameter name: list of values}``, SI units.
    zip : bool
        False: every combination; True: the lists as columns.

    Raises
    ------
    pdbfs.ParameterError
        For an empty dict or list, a value that is not a number, or (zipped)
        lists of different lengths.
    """

    def __init__(self, values: dict, zip: bool = False):
        if not isinstance(values, dict) or not values:
            raise ParameterError("sweep: give the values as a non-empty dict "
                                 "{parameter name: list of values}")
        self.cols = {}
        for name, vals in values.items():
            if not isinstance(name, str):
                raise ParameterError(f"sweep: parameter name {name!r} is not a string")
            arr = np.atleast_1d(np.asarray(vals, dtype=object)).ravel()
            if arr.size == 0:
                raise ParameterError(f"sweep: no values given for {name}")
            try:
                self.cols[name] = arr.astype(float)
            except (TypeError, ValueError):
                bad = next(v for v in arr if not _is_number(v))
                raise ParameterError(f"sweep: {name} = {plain(bad)} is not a number") from None
        self.names, self.zip = list(self.cols), zip
        sizes = [c.size for c in self.cols.values()]
        if zip and len(set(sizes)) > 1:
            raise ParameterError("sweep(grid=False) needs lists of equal length, got "
                                 + ", ".join(f"{n}: {c.size}" for n, c in self.cols.items()))
        self.shape = tuple(sizes)
        self.n = sizes[0] if zip else math.prod(sizes)

    def block(self, i0, i1):
        idx = np.arange(i0, i1)
        if self.zip:
            return np.column_stack([c[idx] for c in self.cols.values()])
        sub = np.unravel_index(idx, self.shape)      # the last name varies fastest
        return np.column_stack([c[s] for c, s in zip(self.cols.values(), sub)])

    @property
    def spec(self):
        """The lists by length, ends and a hash: a manifest stays small for a
        million values."""
        return {"kind": "zip" if self.zip else "grid",
                "values": {n: {"n": int(c.size), "first": float(c[0]), "last": float(c[-1]),
                               "sha256": _digest(c)} for n, c in self.cols.items()}}


def _digest(a) -> str:
    import hashlib
    return hashlib.sha256(np.ascontiguousarray(a, dtype=float).tobytes()).hexdigest()[:16]


def _is_number(v) -> bool:
    try:
        float(v)
        return True
    except (TypeError, ValueError):
        return False


class Sample(PointSet):
    """A sample of ``n`` points over parameter ranges or distributions,
    reproducible from its seed. Sobol' and Monte Carlo points are drawn
    block by block (the same points as drawn whole), so their number is
    bounded by time, not memory; a Latin hypercube is drawn whole.

    Parameters
    ----------
    kind : str
        "lhs": a Latin hypercube; "sobol": a scrambled Sobol' sequence (best
        with ``n`` a power of 2; a warning says so otherwise); "mc": Monte
        Carlo draws.
    n : int
        The number of points (> 0).
    ranges : mapping of str to tuple, optional
        ``{name: (lo, hi)}`` or ``(lo, hi, "log")`` (uniform in the
        logarithm), SI units.
    dists : mapping of str to tuple, optional
        For ``"mc"`` only: ``{name: ("normal", mean, sd) | ("uniform", lo,
        hi) | ("lognormal", median, sigma_ln)}``.
    seed : int
        The seed of the draws.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown kind, a size that is not a whole number > 0, a bad
        range or distribution, a name given both, none at all, or a Latin
        hypercube too big for the memory.

    Examples
    --------
    >>> from pdbfs.studies import Sample
    >>> s = Sample("sobol", 16, ranges={"hammer.v0": (2.0, 3.5), "oil.k": (1e8, 1e9, "log")})
    >>> s.names, s.all().shape
    (['hammer.v0', 'oil.k'], (16, 2))
    """

    def __init__(self, kind: str, n: int, ranges: Mapping[str, tuple] | None = None,
                 dists: Mapping[str, tuple] | None = None, seed: int = 0):
        if kind not in SAMPLERS:
            raise ParameterError(f"unknown sampler {kind!r}; choose one of {', '.join(SAMPLERS)}")
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n <= 0:
            raise ParameterError(f"sample size N = {plain(n)}: must be a whole number > 0")
        self.kind, self.n, self.seed = kind, int(n), int(seed)
        self.ranges = {k: _check_range(k, v) for k, v in (ranges or {}).items()}
        self.dists = {k: _check_dist(k, v) for k, v in (dists or {}).items()}
        if kind != "mc" and self.dists:
            raise ParameterError(f"distributions (--dist) need Monte Carlo sampling (mc:N), "
                                 f"not {kind}")
        both = sorted(set(self.ranges) & set(self.dists))
        if both:
            raise ParameterError(f"{both[0]} has both a range and a distribution")
        self.names = list(self.ranges) + list(self.dists)
        if not self.names:
            raise ParameterError("sampling needs at least one --range NAME=LO:HI"
                                 + (" or --dist" if kind == "mc" else ""))
        d = len(self.names)
        self._u, self._sobol, self._lock = None, None, threading.Lock()
        if kind == "sobol":
            if self.n > SOBOL_MAX:
                raise ParameterError(f"sample sobol:{self.n}: a Sobol' sequence has at most "
                                     f"2**30 = {SOBOL_MAX} points; ask for fewer, or use mc:N")
            if self.n & (self.n - 1):
                low = 1 << (self.n.bit_length() - 1)
                warnings.warn(f"sample sobol:{self.n}: the balance properties of Sobol' points "
                              f"need N to be a power of 2, e.g. {low} or {2 * low}",
                              PdbfsWarning, stacklevel=2)
        elif kind == "lhs":      # stratified as a whole: drawn now, once (forked workers share it)
            require(LHS_BYTES * self.n * d, f"sample lhs:{self.n} over {d} parameter(s)",
                    "a Latin hypercube is drawn whole; ask for fewer points, or use sobol:N or "
                    "mc:N (drawn in blocks)")
            from scipy.stats import qmc          # (a grid, the sweeps' usual points, needs no scipy)
            self._u = qmc.LatinHypercube(d=d, seed=self.seed).random(self.n)

    def _unit(self, i0, i1) -> np.ndarray:
        """Rows i0..i1 of the n x d points in the unit cube: the Latin
        hypercube's, or the Sobol' sequence and the random stream skipped
        ahead to i0 (the same rows as drawn whole)."""
        d = len(self.names)
        if self.kind == "lhs":
            return self._u[i0:i1]
        if self.kind == "sobol":
            with self._lock:
                # scipy skips ahead point by point: blocks asked in order (as a
                # sweep asks them) go on from the last one, at no cost
                engine = self._sobol
                if engine is None or engine.num_generated > i0:
                    from scipy.stats import qmc
                    engine = self._sobol = qmc.Sobol(d=d, scramble=True, seed=self.seed)
                if i0 > engine.num_generated:
                    engine.fast_forward(i0 - engine.num_generated)
                with warnings.catch_warnings():     # said once for the whole sample, above
                    warnings.filterwarnings("ignore", message=".*balance properties")
                    return engine.random(i1 - i0)
        stream = np.random.PCG64(self.seed)     # as np.random.default_rng(seed)
        stream.advance(i0 * d)                  # one 64-bit draw per number
        return np.random.Generator(stream).random((i1 - i0, d))

    def __getstate__(self):          # the engine and its lock stay here
        return {**self.__dict__, "_sobol": None, "_lock": None}

    def __setstate__(self, state):
        self.__dict__.update(state, _lock=threading.Lock())

    def block(self, i0, i1):
        u = self._unit(i0, i1)
        cols = []
        for j, name in enumerate(self.names):
            if name in self.ranges:
                lo, hi, log = self.ranges[name]
                cols.append(np.exp(np.log(lo) + u[:, j] * np.log(hi / lo)) if log
                            else lo + u[:, j] * (hi - lo))
            else:
                cols.append(_ppf(self.dists[name], u[:, j]))
        return np.column_stack(cols)

    @property
    def spec(self):
        return {"kind": self.kind, "n": self.n, "seed": self.seed,
                "ranges": {k: list(v) for k, v in self.ranges.items()},
                "dists": {k: list(v) for k, v in self.dists.items()}}


def _check_range(name, v):
    try:
        lo, hi, *rest = v
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise ParameterError(f"range of {name}: expected (LO, HI), got {plain(v)}") from None
    log = bool(rest and rest[0] in ("log", True))
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
        raise ParameterError(f"range of {name}: LO = {lo:g} must be below HI = {hi:g}")
    if log and lo <= 0:
        raise ParameterError(f"range of {name}: a log range needs LO > 0, got {lo:g}")
    return lo, hi, log


def _check_dist(name, v):
    kind, *args = v
    if kind not in DISTRIBUTIONS:
        raise ParameterError(f"distribution of {name}: unknown {kind!r}; choose one of "
                             f"{', '.join(DISTRIBUTIONS)}")
    if len(args) != DISTRIBUTIONS[kind]:
        raise ParameterError(f"distribution of {name}: {kind} takes {DISTRIBUTIONS[kind]} numbers")
    a, b = map(float, args)
    if kind == "uniform" and not a < b:
        raise ParameterError(f"distribution of {name}: uniform needs LO < HI, got {a:g}, {b:g}")
    if kind in ("normal", "lognormal") and not b > 0:
        raise ParameterError(f"distribution of {name}: the spread must be > 0, got {b:g}")
    if kind == "lognormal" and not a > 0:
        raise ParameterError(f"distribution of {name}: lognormal needs a median > 0, got {a:g}")
    return kind, a, b


def _ppf(dist, u):
    from scipy import stats
    kind, a, b = dist
    if kind == "normal":
        return stats.norm.ppf(u, loc=a, scale=b)
    if kind == "uniform":
        return a + u * (b - a)
    return stats.lognorm.ppf(u, s=b, scale=a)


def parse_range(item: str):
    """``NAME=LO:HI`` or ``NAME=LO:HI:log`` -> (name, (lo, hi[, "log"]))."""
    name, sep, rng = item.partition("=")
    parts = rng.split(":")
    try:
        if not (sep and name.strip()) or len(parts) not in (2, 3) or \
                (len(parts) == 3 and parts[2] != "log"):
            raise ValueError
        lo, hi = float(parts[0]), float(parts[1])
    except ValueError:
        raise ParameterError(f"--range {item!r}: expected NAME=LO:HI or NAME=LO:HI:log, "
                             "e.g. oil.k=1e8:1e9") from None
    return name.strip(), (lo, hi, "log") if len(parts) == 3 else (lo, hi)


def parse_dist(item: str):
    """``NAME=normal:MEAN:SD`` (or uniform:LO:HI, lognormal:MEDIAN:SIGMA)."""
    name, sep, rest = item.partition("=")
    kind, _, args = rest.partition(":")
    if not (sep and name.strip() and kind):
        raise ParameterError(f"--dist {item!r}: expected NAME=normal:MEAN:SD")
    if kind not in DISTRIBUTIONS:
        raise ParameterError(f"--dist {item!r}: unknown distribution {kind!r}; choose one of "
                             f"{', '.join(DISTRIBUTIONS)}")
    try:
        nums = [float(a) for a in args.split(":")]
    except ValueError:
        raise ParameterError(f"--dist {item!r}: the numbers after {kind} are not numbers") from None
    return name.strip(), (kind, *nums)


def parse_sample(text: str):
    """``lhs:N``, ``sobol:N`` or ``mc:N`` -> (kind, N)."""
    kind, _, n = text.partition(":")
    if kind not in SAMPLERS:
        raise ParameterError(f"--sample {text!r}: unknown sampler {kind!r}; choose one of "
                             f"{', '.join(SAMPLERS)} (as lhs:N)")
    try:
        n = int(n)
    except ValueError:
        raise ParameterError(f"--sample {text!r}: N must be a whole number, as in lhs:1000") from None
    if n <= 0:
        raise ParameterError(f"--sample {text!r}: N = {n} must be > 0")
    return kind, n


class Points(PointSet):
    """Points given as an array.

    Parameters
    ----------
    names : sequence of str
        The parameters, the columns.
    array : array_like
        The points, one row each, SI units.
    spec : dict
        What identifies the points (JSON-ready; a resumed sweep checks it),
        e.g. the file they were read from.
    """

    def __init__(self, names: Sequence[str], array: ArrayLike, spec: dict):
        self.names, self.array = list(names), np.atleast_2d(np.asarray(array, dtype=float))
        self.n = self.array.shape[0]
        self._spec = {**spec, "sha256": _digest(self.array)}

    def block(self, i0, i1):
        return self.array[i0:i1]

    @property
    def spec(self):
        return self._spec
