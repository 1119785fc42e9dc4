"""The Simulator: SUNDIALS through casadi.integrator (CVODES for ODE rigs,
IDAS for DAE rigs; integrators cached per setting) or the compiled backend
(``compiled.py``). Tolerances, grid, start and parameters are arguments of
each call: the DAE is never rebuilt. Through CasADi a run stops and restarts
at every time event and every located state event (setup/time_events.py),
as the compiled drivers do."""
from __future__ import annotations

import time
import warnings

import casadi as ca
import numpy as np

from pdbfs.errors import BackendFallbackWarning, ParameterError, PdbfsError, SolverError
from pdbfs.modelling import DAE

from ..results import c_summary
from ..results.contact_impulse import force_role
from ..results.on_grid import OnGrid
from ..results.result import Result
from ..setup import limits
from ..setup import time_events as TE
from ..setup.initialize import solve_start
from ..setup.inputs import RunInputs
from ..state import state_of
from . import compiled as C
from .backends import backend_for_method
from .failures import compiled_failure, walk_failure
from .stats import casadi_stats
from .stiffness import cached_method

#: Adams with fixed-point iteration below so many states (pdbfs_cvode.h's PDBFS_NEWTON_FROM)
NEWTON_FROM = 40
from ..setup.settings import (BACKENDS, MAX_NUM_STEPS, METHODS, check_atol_scale,  # noqa: F401
                              check_settings, default_atol, default_rtol, output_grid)


class Simulator(RunInputs, OnGrid):
    """Integrators of one DAE, cached by their settings."""

    def __init__(self, dae: DAE):
        self.dae = dae
        #: what is kept of the rig for every run (state.py), shared with every Simulator of the DAE
        self.state = state_of(dae)
        self._cache = {}
        self._last_stats = {}
        self._checked = set()     # settings that passed check_settings (inputs.py)
        self._grids = {}          # output grids by (t_end, n_out)
        self._starts = {}         # start vectors by parameter vector (inputs.py)
        self.found_events = {}    # the first state event from a start (setup/time_events.py)
        self.x_names = tuple(dae.x_names)

    @staticmethod
    def of(model) -> "Simulator":
        """The Simulator of a rig or DAE: one per compiled DAE, made on first use."""
        if not isinstance(model, DAE) and not callable(getattr(model, "compile", None)):
            raise ParameterError(f"rig = {model!r}: give a rig (a Component) or its compiled DAE, "
                                 f"not a {type(model).__name__}")
        dae = model if isinstance(model, DAE) else model.compile()
        state = state_of(dae)
        if state.simulator is None:
            state.simulator = Simulator(dae)
        return state.simulator

    def z_guess(self, p) -> np.ndarray:
        """The algebraic variables' start guesses at parameters ``p`` (empty for an ODE rig)."""
        dae = self.dae
        if dae.is_ode:
            return np.zeros(0)
        return ca.Function("z0", [dae.p], [dae.z0])(p).full().ravel()

    def resolve_method(self, method, p, x0, span, backend="casadi") -> str:
        """``method``, or for "auto" the one stiffness.auto_method picks
        for this start and time span, once per class of runs
        (stiffness.cached_method): in the compiled backend the cheapest of
        "erk", "adams" and "bdf" by its cost estimate (the modes from the
        compiled library), through CasADi of "adams" and "bdf"."""
        if method != "auto":
            return method
        # (backend "c" here: run() has refused a DAE rig already)
        return cached_method(self, np.asarray(p, float), np.asarray(x0, float), float(span),
                             backend)

    def resolve_backend(self, backend: str) -> str:
        """``backend``; "auto": "c" where it can be built, else "casadi" (once per DAE)."""
        if backend != "auto":
            return backend
        chosen = self._cache.get("backend")
        if chosen is None:
            dae = self.dae
            chosen = "casadi"
            if dae.is_ode and dae.x.numel():
                try:
                    self.compiled()
                    chosen = "c"
                except ParameterError:
                    raise
                except PdbfsError as err:
                    first = str(err).splitlines()[0] if str(err) else type(err).__name__
                    warnings.warn(f"rig {dae.name}: the compiled backend is not available "
                                  f"({first}); simulating with CasADi", BackendFallbackWarning,
                                  stacklevel=4)
            self._cache["backend"] = chosen
        return chosen

    def integrator(self, grid, rtol, atol, method, max_step, scaled=False,
                   max_num_steps=MAX_NUM_STEPS, xdot0=None, keep=True, quad=None, watch=False):
        """A casadi integrator for these settings (cached). ``xdot0`` (DAE
        rigs) is IDAS's guess of der(x) at the start, which its consistent
        initialisation needs; such integrators are built per call. ``quad``: an
        output integrated as a quadrature (the same steps and states);
        ``watch``: then the positive and negative parts of each state-event
        indicator too (time_events.py). A ``scaled`` one takes (t0, h,
        t_lim) after p: tau in [0, 1] covers [t0, t0 + h], the right-hand
        side seeing time min(t, t_lim)."""
        self.check_settings(rtol, atol, method, max_step, max_num_steps)
        if method == "auto":
            raise ParameterError("method='auto' is resolved by the caller (resolve_method)")
        key = (np.asarray(grid, float).tobytes(), rtol, atol, method, max_step, scaled,
               max_num_steps, quad, watch)
        if xdot0 is not None or key not in self._cache:
            dae = self.dae
            opts = {"abstol": atol, "reltol": rtol, "max_num_steps": int(max_num_steps),
                    "disable_internal_warnings": True, "show_eval_warnings": False}
            if max_step is not None:
                opts["max_step_size"] = max_step
            if dae.is_ode:
                opts["linear_multistep_method"] = method
            if method == "adams" and dae.is_ode and dae.x.numel() < NEWTON_FROM:
                # fixed point, as the compiled driver (Newton let errors of 20 times the
                # tolerance through on a short contact)
                opts["nonlinear_solver_iteration"] = "functional"
            if xdot0 is not None:
                opts["init_xdot"] = [float(v) for v in xdot0]
            spec = TE.integrator_spec(dae, quad, watch, scaled)
            plugin = "cvodes" if dae.is_ode else "idas"
            # the output grid includes t0: its z is then the consistent one
            F = ca.integrator("sim", plugin, spec, float(grid[0]), list(grid), opts)
            if xdot0 is not None or not keep:     # (pieces between switches: one-off grids)
                return F
            self._cache[key] = F
        return self._cache[key]

    def consistent_start(self, t0, x0, p):
        """(z, der(x)) at a DAE rig's start: z by Newton from the declared guesses."""
        dae = self.dae
        rf = self._cache.get("rootfinder")
        if rf is None:
            tp = ca.vertcat(dae.t, dae.x, dae.p)
            rf = ca.rootfinder("z0", "newton", {"x": dae.z, "p": tp, "g": dae.alg},
                               {"error_on_fail": False})
            self._cache["rootfinder"] = rf
        z = self.z_guess(p)
        try:
            z_new = rf(z, np.concatenate([[t0], x0, p])).full().ravel()
            if np.all(np.isfinite(z_new)):
                z = z_new
        except RuntimeError:
            pass   # IDAS's own initialisation gets another go from the guess
        xdot = self.dae.function("ode")(t0, x0, z, p).full().ravel()
        return z, xdot

    def step(self, x, p, t0, h, rtol, atol, method, max_step=None, backend="casadi",
             max_num_steps=MAX_NUM_STEPS):
        """State at t0 + h from state x at t0 (h > 0). "auto" is judged at
        the rig's start, not at x: one choice for every step of a run."""
        if self.dae.x.numel() == 0:
            return np.zeros(0), self.prescribed(np.array([t0 + h]), p)[1][:, -1]
        backend = self.resolve_backend(backend)
        method = self.resolve_method(method, p, self.start_vector(p), h, backend) \
            if method == "auto" else method
        if backend == "c":
            grid = np.array([t0, t0 + h], dtype=float)
            if not grid[1] - grid[0] > 8 * np.finfo(float).eps * np.max(np.abs(grid)):
                return np.array(x, dtype=float), np.zeros(0)   # closer than CVODE can step
            X = self.integrate_c(grid, np.asarray(x, float), p, rtol, atol, method, max_step,
                                 max_num_steps)
            return X[:, -1], np.zeros(0)
        X, Z, _ = TE.pieces(self, np.array([t0, t0 + h]), np.asarray(x, float), p, rtol, atol,
                            method, max_step, max_num_steps)
        return X[:, -1], Z[:, -1]

    def run(self, t_end=0.02, n_out=2001, *, t_out=None, params=None, start=None,
            rtol=None, atol=None, method="auto", max_step=None,
            max_num_steps=MAX_NUM_STEPS, backend="auto", initial=None):
        """One run, as simulate(). What depends on the rig alone is made once
        and kept in its state: what the settings decide (run_settings), its
        own start (own_start), the method "auto" picks for a class of runs;
        what a caller gives is checked every time."""
        asked = backend
        backend, grid, t_addr = self.run_settings(t_end, n_out, t_out, rtol, atol, method,
                                                  max_step, max_num_steps, backend, initial)
        if params is None and start is None and initial is None:
            p, x0, init = self.own_start(grid[0])
        else:
            p = self.param_vector(params)
            x0 = init = self.start_vector(p, start)
            if initial is not None or self._needs_solving():
                x0, init = solve_start(self, p, x0, initial, float(grid[0]))
        if atol is not None:
            check_atol_scale(self.dae, x0, atol)
        method = self.resolve_method(method, p, x0, grid[-1] - grid[0], backend)
        backend = backend_for_method(self, asked, backend, method)
        rtol = default_rtol(method, rtol)
        atol = default_atol(rtol, atol)
        return self._run(grid, p, x0, init, rtol, atol, method, max_step, max_num_steps, backend,
                         t_addr)

    def _run(self, grid, p, x0, init, rtol, atol, method, max_step, max_num_steps, backend,
             t_addr=None):
        """One run on ``grid`` (``t_addr``: its data's address where it is a kept,
        read-only grid); the Result copies ``grid`` and ``p`` when first read."""
        wall = time.perf_counter()
        fast = states = impulse = None
        if backend == "c":
            X, fast, states, stats = self._run_c(grid, x0, p, rtol, atol, method, max_step,
                                                 max_num_steps, t_addr)
            Z = np.zeros((0, grid.size))
        else:
            X, Z = self.integrate(grid, x0, p, rtol, atol, method, max_step, max_num_steps)
            stats, impulse = self._last_stats, self._last_impulse
        stats = dict(stats, wall_time=time.perf_counter() - wall, backend=backend)
        settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                    "max_num_steps": max_num_steps, "backend": backend}
        limits.check(self, grid, X, Z, p, settings)   # a variable out of its declared range
        return Result(self, grid, p, X, Z, settings, stats, fast_summary=fast, initial=init,
                      states=states, own_stats=True, impulse=impulse)

    def integrate(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS):
        """(X, Z): states and algebraic variables on ``grid`` through CasADi,
        settings checked (and the contact force's impulse on it, for the summary)."""
        self._last_impulse = None
        if self.dae.x.numel() == 0:
            return self.prescribed(grid, p)
        X, Z, self._last_impulse = self.located(grid, x0, p, rtol, atol, method, max_step,
                                                max_num_steps, force_role(self.dae))
        return X, Z

    def integrate_shifted(self, grid, x0, p, rtol, atol, method, max_step,
                          max_num_steps=MAX_NUM_STEPS):
        """As integrate(), from x0 at grid[0] > 0, on time-scaled integrators
        (one for every grid of the same shape: no rebuild per window)."""
        if self.dae.x.numel() == 0:
            return self.prescribed(grid, p)
        return self.located(grid, x0, p, rtol, atol, method, max_step, max_num_steps)[:2]

    def located(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps, force=None):
        """(X, Z, Q): time_events.pieces, a failure a SolverError saying where, X checked finite."""
        try:
            X, Z, Q = TE.pieces(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps, force)
        except RuntimeError as err:
            raise self._failure(grid, x0, p, rtol, atol, method, max_step, err,
                                max_num_steps) from None
        self._check_finite(grid, X if Q is None else np.vstack([X, Q]))
        return X, Z, Q

    def scaled_run(self, grid, x0, p, s, force=None, watch=False, t_lim=np.inf):
        """(X, Z, Q) on ``grid`` from x0 at grid[0]: one call of the
        time-scaled integrator (settings ``s``: rtol, atol, method,
        max_step, max_num_steps), cached by the grid's shape; Q the
        quadratures' rows (integrator(): the output ``force``, then with
        ``watch`` the indicators' parts), None without any."""
        rtol, atol, method, max_step, max_num_steps = s
        t0, span = float(grid[0]), float(grid[-1] - grid[0])
        if not span > 0:   # a NaN output time would keep CVODE busy for ever
            raise ValueError(f"scaled_run: the grid must span a positive time, not {span!r}")
        tau = (np.asarray(grid, float) - t0) / span
        even = np.linspace(0.0, 1.0, tau.size)   # equal steps: one integrator for every such grid
        tau = even if np.all(np.abs(tau - even) <= 1e-13) else tau
        z0, xdot0 = (self.z_guess(p), None) if self.dae.is_ode else \
            self.consistent_start(t0, x0, p)
        F = self.integrator(tau, rtol, atol, method, max_step, scaled=True,
                            max_num_steps=max_num_steps, quad=force, watch=watch,
                            xdot0=None if xdot0 is None else span * xdot0,
                            keep=tau is even or tau.size == 2)
        r = _call(F, x0=x0, p=np.concatenate([p, [t0, span, t_lim]]), z0=z0)  # (a failure:
        X = r["xf"].full()                        # the caller's pieces() call says where)
        Z = r["zf"].full().reshape(self.dae.z.numel(), X.shape[1])
        Q = r["qf"].full().reshape(-1, X.shape[1]) if r["qf"].numel() else None
        self._last_stats = casadi_stats(F.stats(), method if self.dae.is_ode else "bdf")
        return X, Z, Q

    def prescribed(self, grid, p):
        """A rig whose motion is prescribed (no state): nothing to integrate;
        algebraic variables are solved point by point."""
        n = len(grid)
        Z = np.column_stack([self.consistent_start(t, np.zeros(0), p)[0] for t in grid]) \
            if self.dae.z.numel() else np.zeros((0, n))
        self._last_stats = {"steps": 0, "rhs_evals": 0, "jac_evals": 0, "root_events": 0,
                            "method": "none (no state)"}
        return np.zeros((0, n)), Z

    def _check_finite(self, grid, X):
        if not np.all(np.isfinite(X)):
            k = int(np.argmax(~np.all(np.isfinite(X), axis=0)))
            raise SolverError(f"rig {self.dae.name}: the solution became NaN or infinite at "
                              f"t = {grid[k]:.6g} s; check parameter values (a stiffness or "
                              "exponent far out of range?)")

    def compiled(self, method: str | None = None):
        """The DAE compiled to a shared library (compiled.py), built once; one
        with CVODE when ``method`` needs it."""
        return C.compiled(self.dae, cvode=method in C.CVODE_METHODS)

    def integrate_c(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps):
        """States on ``grid`` (nx x len(grid)) from the compiled driver, the
        run's statistics in ``_last_stats`` (arguments checked by the caller)."""
        if self.nx == 0:
            return self.prescribed(grid, p)[0]
        X, st = self.compiled(method).run(grid, x0, p, rtol, atol, method, max_step,
                                          max_num_steps)
        if not st.ok:
            raise compiled_failure(self.dae, grid, st)
        stats = st.stats
        stats.pop("wall_time", None)
        self._last_stats = stats
        # the driver refuses a solution that is not finite (RC_NOT_FINITE), so
        # a sum (a NaN or infinity anywhere makes it one) is all it takes here
        if not np.isfinite(np.add.reduce(X, axis=None)):
            self._check_finite(grid, X)
        return X

    def _run_c(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps, t_addr=None):
        """A compiled run of the rig from t = 0 on ``grid``: (states, the run's
        own summary (c_summary.py) or None, None, its statistics) or, with
        the explicit method, (None, its summary, a function that makes the
        states when they are first read: a summary alone needs no dense
        output, its statistics)."""
        lib = self.compiled(method) if self.nx else None
        if lib is None or grid[0] != 0.0 or not c_summary.usable(self.dae, lib):
            X = self.integrate_c(grid, x0, p, rtol, atol, method, max_step, max_num_steps)
            return X, None, None, self._last_stats
        X, st, values, code, note, kept = lib.run_summary(
            grid, x0, p, rtol, atol, method, max_step, max_num_steps, checked=True, keep=True,
            t_addr=t_addr)
        if not st.ok:
            raise compiled_failure(self.dae, grid, st)
        stats = st.stats
        stats.pop("wall_time", None)
        fast = (values, code, note)
        if kept is not None:
            return None, fast, lambda: self._kept_states(kept, grid), stats
        if not np.isfinite(np.add.reduce(X, axis=None)):
            self._check_finite(grid, X)
        return X, fast, None, stats

    def _kept_states(self, kept, grid):
        """The states of a kept run on its grid (integrate_c), checked as a run's."""
        X, code, message = kept.states()
        if code:
            raise SolverError(f"rig {self.dae.name}: the states on the output grid could not be "
                              f"made from the run: {message}")
        if not np.isfinite(np.add.reduce(X, axis=None)):
            self._check_finite(grid, X)
        return X

    #: (grid, x0, p, rtol, atol, method, max_step, err, max_num_steps): the SolverError to raise
    _failure = walk_failure


def _call(F, **args):
    """F(**args); CasADi answers Ctrl-C with empty results or a RuntimeError
    naming it: raise it as Python would."""
    try:
        r = F(**args)
    except RuntimeError as err:
        if "KeyboardInterrupt" in str(err):
            raise KeyboardInterrupt from None
        raise
    if r.get("xf") is None:
        raise KeyboardInterrupt
    return r
