"""What a run is given, checked and turned into vectors (mixed into
Simulator): parameters, start values, the output grid and the settings.
What depends on the rig alone is made and checked once per Simulator and
copied for each run (the default parameter and start vectors, the grid of a
(t_end, n_out), settings that passed), so that a run costs microseconds of
Python; anything given is checked every time."""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError
from pdbfs.modelling import check_value
from pdbfs.modelling.passes import reduced_start
from pdbfs.modelling import quantity

from .initialize import check_initial, needs_solving, solve_start
from .memory import require, run_bytes
from .settings import MAX_NUM_STEPS, check_settings, default_rtol, mapping, output_grid
from .vectorize import vectorize


#: Functions of up to this many instructions are evaluated by numpy replay (about
#: 0.3 us an instruction against about 15 us a CasADi call from Python)
REPLAY_UP_TO = 40


class RunInputs:
    """Mixed into Simulator (which has ``dae``, ``state``, ``_cache``,
    ``_checked``, ``_grids``, ``_starts`` and ``x_names``)."""

    check_settings = staticmethod(check_settings)
    #: start vectors kept by their parameter vector (``_starts``): a loop over new
    #: parameters makes the rest anew each time
    STARTS_MAX = 256

    def param_vector(self, params=None) -> np.ndarray:
        """The parameter vector: the defaults with ``params`` set, every value
        checked (bounds, the components' conditions). The defaults' vector is
        checked once and kept (a fresh copy each call)."""
        if params is None or (type(params) is dict and not params):
            base = self._cache.get("p0")
            if base is None or base[0] is not self.dae.params:   # a new parameter list: again
                base = self._cache["p0"] = (self.dae.params, self._param_vector(None))
            return base[1].copy()
        return self._param_vector(params)

    def _param_vector(self, params) -> np.ndarray:
        dae = self.dae
        known = self._cache.get("p_index")
        if known is None or known[0] is not dae.params:      # a new parameter list: again
            known = self._cache["p_index"] = (dae.params, dae.p_default(),
                                              {n: i for i, n in enumerate(dae.p_names)})
        p, index = known[1].copy(), known[2]
        for name, value in mapping(params, "params").items():
            if name not in index:
                if name in dae.calculated:
                    expr, info = dae.calculated[name]
                    if expr.is_constant():       # a number the rig fixes, e.g. a start at rest
                        raise ParameterError(f"{name} is fixed by rig {dae.name} at "
                                             f"{quantity(float(expr), info.unit)} and cannot be set")
                    raise ParameterError(f"{name} is computed from other parameters "
                                         "and cannot be set; set those instead")
                import difflib
                close = difflib.get_close_matches(name, dae.p_names, n=3)
                hint = f"; did you mean {', '.join(close)}?" if close else \
                    "; `pdbfs params` lists them"
                raise ParameterError(f"unknown parameter {name!r} of rig {dae.name}{hint}")
            info = dae.params[index[name]]
            p[index[name]] = check_value(value, name, info)
        conds = getattr(dae, "conditions", None)
        if conds:                    # the components' physical consistency
            v = self.numeric("conditions", lambda: ca.Function(
                "conditions", [dae.p], [ca.vertcat(*[e for e, _ in conds])]))(p)
            if not (v >= 0).all():
                dae.check_conditions(p)      # (CasADi's verdict, naming what is wrong)
        if params and getattr(dae, "reduced_starts", None):
            # a start of a state index reduction made algebraic is not free: never ignored
            reduced_start.check(dae, p, ParameterError)
        return p

    def start_vector(self, p, start=None) -> np.ndarray:
        """The start values at parameters ``p``, with ``start`` ({state: value}) put in, checked."""
        key = np.asarray(p, float).tobytes()     # the start of these parameters, once
        known = self._starts.get(key)
        if known is None:
            if len(self._starts) >= self.STARTS_MAX:    # a loop over new parameters: a few kept
                self._starts.clear()
            x0 = self.numeric("start", lambda: self.dae.function("start"))(p)
            known = self._starts[key] = (x0, all(map(math.isfinite, x0.tolist())))
        if known[1] and (start is None or (type(start) is dict and not start)):
            return known[0].copy()                       # nothing to set, finite: as it is
        x0 = known[0].copy()
        index = {n: i for i, n in enumerate(self.x_names)}
        for name, value in mapping(start, "start", "'hammer.s': 0.0").items():
            if name in {n for n, *_ in getattr(self.dae, "reduced_starts", ())}:
                raise ParameterError(
                    f"{name} is not a state of rig {self.dae.name}: index reduction computes it "
                    f"from {'; '.join(self.dae.reduced_by)}, so its start is not free")
            if name not in index:
                raise ParameterError(f"{name!r} is not a state of rig {self.dae.name}; "
                                     f"states: {', '.join(self.dae.x_names)}")
            x0[index[name]] = check_value(value, f"start value of {name}",
                                          _Unbounded(self.dae.x_info[index[name]]))
        if not np.all(np.isfinite(x0)):
            bad = [n for n, v in zip(self.dae.x_names, x0) if not np.isfinite(v)]
            raise ParameterError(f"start values are not finite: {', '.join(bad)}")
        return x0

    def numeric(self, name, make):
        """The first output of the CasADi Function ``make()`` as a function of
        numpy vectors, cached: for a short Function by vectorize.py's replay of
        its instructions (a quarter of the cost of a CasADi call from Python;
        a long one costs more that way). Where the rig's compiled library is
        loaded, the start values and the conditions are its C (a microsecond:
        a loop over new parameters pays for these at every run)."""
        lib = self.state.compiled
        key = ("numeric", name, lib is not None)
        f = self._cache.get(key)
        if f is None and lib is not None and (name == "conditions" or
                                              name == "start" and not self._needs_solving()):
            f = self._cache[key] = getattr(lib, name)
        if f is None:
            fun = make()
            fast = vectorize(fun) if fun.n_instructions() <= REPLAY_UP_TO else None
            if fast is not None:
                f = lambda *a: fast(*[np.reshape(np.asarray(x, float), (-1, 1))  # noqa: E731
                                      for x in a])[0][:, 0].copy()
            else:
                f = lambda *a: np.array(fun(*a), dtype=float).ravel()   # noqa: E731
            self._cache[key] = f
        return f

    def settings_ok(self, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS,
                    backend="auto"):
        """check_settings, remembered for settings that passed (keyed with
        their types: 1 and True are not the same setting)."""
        args = (rtol, atol, method, max_step, max_num_steps, backend)
        try:
            key = (type(rtol), rtol, type(atol), atol, type(method), method, type(max_step),
                   max_step, type(max_num_steps), max_num_steps, type(backend), backend)
            if key in self._checked:
                return
        except TypeError:        # unhashable (a list where a number belongs): checked below
            key = None
        self.check_settings(*args)
        if key is not None and len(self._checked) < 1000:
            self._checked.add(key)

    def run_settings(self, t_end, n_out, t_out, rtol, atol, method, max_step, max_num_steps,
                     backend, initial):
        """Simulator.run's settings checked, before any work: (the backend
        resolved, the output grid (read-only: the Result copies it when
        first read), its address where it is a kept grid, else None). Made
        once per settings (their values and types: 1 and 1.0 are not the
        same request) and kept in the rig's state; a grid given as
        ``t_out`` is checked at every run."""
        key = None
        if t_out is None and initial is None:
            key = (type(t_end), t_end, type(n_out), n_out, type(rtol), rtol, type(atol), atol,
                   type(method), method, type(max_step), max_step, type(max_num_steps),
                   max_num_steps, type(backend), backend)
            try:
                found = self.state.runs.get(key)
            except TypeError:        # unhashable (a list where a number belongs): checked below
                found = key = None
            if found is not None:
                return found
        self.settings_ok(default_rtol(method, rtol), atol, method, max_step, max_num_steps,
                         backend)
        if initial is not None:
            check_initial(initial, self.dae)
        asked, backend = backend, self.resolve_backend(backend)
        if backend == "c" and self.nx:   # a DAE rig is refused before anything else (and
            # backend="c" with a CVODE method without its sources: "auto" falls back later)
            self.compiled(method if asked == "c" else None)
        n_points = np.size(t_out) if t_out is not None else n_out
        if isinstance(n_points, (int, np.integer)):     # before the grid itself is allocated
            per_point = self._cache.get("bytes/point")
            if per_point is None:
                per_point = self._cache["bytes/point"] = run_bytes(self.dae, 1)
            require(per_point * n_points, f"rig {self.dae.name}: {n_points} output points",
                    "ask for fewer (n_out, --n-out)")
        if t_out is not None:       # the run's own copy: the caller's array stays the caller's
            grid = output_grid(t_end, n_out, t_out).copy()
            grid.flags.writeable = False
            return backend, grid, None
        found = (backend, *self.grid_kept(t_end, n_out))
        if key is not None:
            if len(self.state.runs) > 64:       # loops over settings: keep a few
                self.state.runs.clear()
            self.state.runs[key] = found
        return found

    def own_start(self, t0=0.0) -> tuple:
        """(p, x0, the start's record) of the rig's own parameters and declared
        start, p and x0 read-only: made once per parameter list (a start the
        initial equations solve, at every run: its record is the Result's)."""
        own = self.state.own_start
        if own is None or own[0] is not self.dae.params:
            p = self.param_vector(None)
            x0 = self.start_vector(p)
            p.flags.writeable = x0.flags.writeable = False
            own = self.state.own_start = (self.dae.params, p, x0)
        if self._needs_solving():
            return (own[1], *solve_start(self, own[1].copy(), own[2].copy(), None, float(t0)))
        return own[1], own[2], own[2]

    def _needs_solving(self) -> bool:
        """Whether the rig's declared start must be solved (free states, initial
        equations); decided once."""
        need = self._cache.get("needs_solving")
        if need is None:
            need = self._cache["needs_solving"] = needs_solving(self.dae, None)
        return need

    @property
    def nx(self) -> int:
        """The number of states."""
        n = self.__dict__.get("_nx")
        if n is None:
            n = self._nx = int(self.dae.x.numel())
        return n

    def grid(self, t_end, n_out, t_out=None) -> np.ndarray:
        """The output grid (settings.output_grid): a new array, the grid of a
        (t_end, n_out) made and checked once."""
        if t_out is not None:
            return output_grid(t_end, n_out, t_out)
        return self.grid_kept(t_end, n_out)[0].copy()

    def grid_kept(self, t_end, n_out):
        """(the grid of ``t_end`` and ``n_out``, read-only, its data's address),
        made and checked once."""
        try:
            key = (type(t_end), t_end, type(n_out), n_out)
            kept = self._grids.get(key)
        except TypeError:
            kept, key = None, None
        if kept is None:
            g = output_grid(t_end, n_out)
            if not (np.all(np.diff(g) > 0) and np.isfinite(g[-1])):   # a t_end under n_out ulps
                raise ParameterError(f"t_end = {t_end}: too short for {n_out} distinct output "
                                     "times")
            g.flags.writeable = False
            kept = (g, g.ctypes.data)
            if key is not None:
                if len(self._grids) > 16:       # sweeps over t_end: keep a few
                    self._grids.clear()
                self._grids[key] = kept
        return kept


class _Unbounded:
    def __init__(self, info):
        self.unit, self.description = info.unit, info.description
        self.min = self.max = None
        self.positive = False
