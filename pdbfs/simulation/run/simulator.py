"""The Simulator: SUNDIALS through casadi.integrator (CVODES for ODE rigs,
IDAS for DAE rigs; integrators cached per setting) or the compiled backend
(``compiled.py``). Tolerances, grid, start and parameters are arguments of
each call: the DAE is never rebuilt. Kinks are integrated through with error
control, checked against an event-located reference in the tests."""
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
from . import replay
from .backends import backend_for_method
from .failures import compiled_failure, walk_failure
from .stats import casadi_stats
from .stiffness import auto_method
from ..setup.settings import (BACKENDS, MAX_NUM_STEPS, METHODS, check_settings,  # noqa: F401
                              default_atol, default_rtol, output_grid)


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
        for this start and time span (cached: repeated runs pay nothing): in
        the compiled backend the cheapest of "erk", "adams" and "bdf" by its
        cost estimate (the modes from the compiled library), through CasADi
        of "adams" and "bdf"."""
        if method != "auto":
            return method
        key = ("auto", backend == "c", np.asarray(p, float).tobytes(),
               np.asarray(x0, float).tobytes(), float(span))
        found = self._cache.get(key)
        if found is None:
            # (backend "c" here: run() has refused a DAE rig already)
            lib = self.compiled() if backend == "c" and self.nx else None
            found = auto_method(self.dae, p, x0, span, lib, backend)
            if len(self._cache) < self.CACHE_MAX:   # a loop over new parameters: bounded
                self._cache[key] = found
        return found[0]

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
                   max_num_steps=MAX_NUM_STEPS, xdot0=None, keep=True, quad=None):
        """A casadi integrator for these settings (cached). ``xdot0`` (DAE
        rigs) is IDAS's guess of der(x) at the start, which its consistent
        initialisation needs; such integrators are built per call. ``quad``: an
        output integrated as a quadrature (the same steps and states)."""
        self.check_settings(rtol, atol, method, max_step, max_num_steps)
        if method == "auto":
            raise ParameterError("method='auto' is resolved by the caller (resolve_method)")
        key = (np.asarray(grid, float).tobytes(), rtol, atol, method, max_step, scaled,
               max_num_steps, quad)
        if xdot0 is not None or key not in self._cache:
            dae = self.dae
            opts = {"abstol": atol, "reltol": rtol, "max_num_steps": int(max_num_steps),
                    "disable_internal_warnings": True, "show_eval_warnings": False}
            if max_step is not None:
                opts["max_step_size"] = max_step
            if dae.is_ode:
                opts["linear_multistep_method"] = method
            if xdot0 is not None:
                opts["init_xdot"] = [float(v) for v in xdot0]
            spec = {"x": dae.x, "z": dae.z, "p": dae.p, "t": dae.t, "ode": dae.ode,
                    "alg": dae.alg, "quad": dae.y[dae.y_names.index(quad)] if quad else []}
            if scaled:   # tau in [0, 1] covers [t0, t0 + h]: one object for any interval
                t0, h, tau = ca.SX.sym("t0"), ca.SX.sym("h"), ca.SX.sym("tau")
                subs = lambda e: ca.substitute(e, dae.t, t0 + h * tau)
                spec = {"x": dae.x, "z": dae.z, "p": ca.vertcat(dae.p, t0, h), "t": tau,
                        "ode": h * subs(dae.ode), "alg": subs(dae.alg), "quad": h * subs(ca.SX(spec["quad"]))}
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
        if TE.breakpoints(self.dae, p, t0, t0 + h).size:     # a switch inside: stop there
            X, Z = TE.pieces(self, np.array([t0, t0 + h]), np.asarray(x, float), p, rtol, atol,
                                method, max_step, max_num_steps)
            return X[:, -1], Z[:, -1]
        z0, xdot0 = (self.z_guess(p), None) if self.dae.is_ode else \
            self.consistent_start(t0, x, p)
        F = self.integrator((0.0, 1.0), rtol, atol, method, max_step, scaled=True,
                            max_num_steps=max_num_steps,
                            xdot0=None if xdot0 is None else h * xdot0)   # d/dtau = h d/dt
        r = _call(F, x0=x, p=np.concatenate([p, [t0, h]]), z0=z0)
        return r["xf"].full()[:, -1], r["zf"].full().reshape(-1, 2)[:, -1]

    def run(self, t_end=0.02, n_out=2001, *, t_out=None, params=None, start=None,
            rtol=None, atol=None, method="auto", max_step=None,
            max_num_steps=MAX_NUM_STEPS, backend="auto", initial=None):
        """One run, as simulate(). From the rig's start (its parameters or new ones), what the
        checks decide is kept as a plan for the next run with the same settings (and types)."""
        dae = self.dae
        key = plan = None
        asked = backend
        if t_out is None and start is None and initial is None:
            try:
                key = replay.key(t_end, n_out, rtol, atol, method, max_step, max_num_steps,
                                 backend, params is not None)
                plan = self._cache.get(key)
            except TypeError:         # unhashable (a list where a number belongs): checked below
                key = None
            if plan is not None and plan.params is not dae.params:
                plan = None
            elif plan is not None and params is None:
                return replay.run(self, plan)
        if plan is None:
            backend, grid, kept_grid = self.run_settings(t_end, n_out, t_out, rtol, atol, method,
                                                         max_step, max_num_steps, backend, initial)
        else:             # new parameters with the settings of a plan: checked for it
            backend, grid, kept_grid = plan.settings["backend"], plan.grid, (plan.grid, plan.t_addr)
        p = self.param_vector(params)
        x0 = self.start_vector(p, start)
        if initial is None and not self._needs_solving():
            init = x0       # the start as declared: Result.initial makes its record on demand
        else:
            x0, init = solve_start(self, p, x0, initial, float(grid[0]))
        method = self.resolve_method(method, p, x0, grid[-1] - grid[0], backend)
        if plan is None:
            backend = backend_for_method(self, asked, backend, method)
        rtol = default_rtol(method, rtol)
        atol = default_atol(rtol, atol)
        if plan is not None:
            if plan.lib is not None and method == plan.settings["method"]:
                return replay.run(self, plan, p, x0)      # its compiled call, these p and x0
            grid = grid.copy()
        elif key is not None and init is x0 and len(self._cache) < self.CACHE_MAX:
            self._cache[key] = replay.make_plan(self, key, kept_grid, p, x0, rtol, atol, method,
                                                max_step, max_num_steps, backend)
        return self._run(grid, p, x0, init, rtol, atol, method, max_step, max_num_steps, backend,
                         c_grid=kept_grid)

    def _run(self, grid, p, x0, init, rtol, atol, method, max_step, max_num_steps, backend,
             c_grid=None):
        """One run on ``grid``; ``c_grid``: (the same times, read-only, their address)."""
        wall = time.perf_counter()
        fast = states = None
        if backend == "c":
            X, fast, states = self.integrate_c(grid, x0, p, rtol, atol, method, max_step,
                                               max_num_steps, summary=True, c_grid=c_grid)
            Z = np.zeros((0, grid.size))
        else:
            X, Z = self.integrate(grid, x0, p, rtol, atol, method, max_step, max_num_steps)
        stats = dict(self._last_stats, wall_time=time.perf_counter() - wall, backend=backend)
        settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                    "max_num_steps": max_num_steps, "backend": backend}
        limits.check(self, grid, X, Z, p, settings)   # a variable out of its declared range
        return Result(self, grid, p, X, Z, settings, stats, fast_summary=fast, initial=init,
                      states=states, own_stats=True,
                      impulse=None if backend == "c" else self._last_impulse)

    def integrate(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS):
        """(X, Z): states and algebraic variables on ``grid`` through CasADi, settings checked."""
        self._last_impulse = None      # the contact force's impulse on grid, for the summary
        if self.dae.x.numel() == 0:
            return self.prescribed(grid, p)
        if TE.breakpoints(self.dae, p, grid[0], grid[-1]).size:
            return TE.pieces(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps)
        z0, xdot0 = (self.z_guess(p), None) if self.dae.is_ode else \
            self.consistent_start(grid[0], x0, p)
        F = self.integrator(grid, rtol, atol, method, max_step, max_num_steps=max_num_steps,
                            xdot0=xdot0, quad=force_role(self.dae))
        nz = self.dae.z.numel()
        try:
            r = _call(F, x0=x0, p=p, z0=z0)
            X = r["xf"].full()
            Z = r["zf"].full().reshape(nz, X.shape[1])
            self._last_impulse = r["qf"].full().ravel() if r["qf"].numel() else None
        except RuntimeError as err:
            raise self._failure(grid, x0, p, rtol, atol, method, max_step, err,
                                max_num_steps) from None
        self._last_stats = casadi_stats(F.stats(), method if self.dae.is_ode else "bdf")
        self._check_finite(grid, X)
        return X, Z

    def integrate_shifted(self, grid, x0, p, rtol, atol, method, max_step,
                          max_num_steps=MAX_NUM_STEPS):
        """As integrate(), from x0 at grid[0] > 0, on one time-scaled
        integrator for every grid of the same shape (no rebuild per window)."""
        if self.dae.x.numel() == 0:
            return self.prescribed(grid, p)
        if TE.breakpoints(self.dae, p, grid[0], grid[-1]).size:
            return TE.pieces(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps)
        return self._shifted(grid, x0, p, rtol, atol, method, max_step, max_num_steps)

    def _shifted(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps, keep=True):
        t0, span = float(grid[0]), float(grid[-1] - grid[0])
        if not span > 0:   # a NaN output time would keep CVODE busy for ever
            raise ValueError(f"integrate_shifted: the grid must span a positive time, not {span!r}")
        tau = (np.asarray(grid, float) - t0) / span
        z0, xdot0 = (self.z_guess(p), None) if self.dae.is_ode else \
            self.consistent_start(t0, x0, p)
        F = self.integrator(tau, rtol, atol, method, max_step, scaled=True,
                            max_num_steps=max_num_steps,
                            xdot0=None if xdot0 is None else span * xdot0, keep=keep)
        try:
            r = _call(F, x0=x0, p=np.concatenate([p, [t0, span]]), z0=z0)
        except RuntimeError as err:
            raise self._failure(grid, x0, p, rtol, atol, method, max_step, err,
                                max_num_steps) from None
        X = r["xf"].full()
        Z = r["zf"].full().reshape(self.dae.z.numel(), X.shape[1])
        self._last_stats = casadi_stats(F.stats(), method if self.dae.is_ode else "bdf")
        self._check_finite(grid, X)
        return X, Z

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

    def integrate_c(self, grid, x0, p, rtol, atol, method, max_step, max_num_steps,
                    summary=False, c_grid=None):
        """States on ``grid`` (nx x len(grid)) from the compiled driver; with
        ``summary``, (states, the run's own summary (c_summary.py) or None,
        None) or, with the explicit method, (None, its summary, a function
        that makes the states when they are first read: a summary alone
        needs no dense output) (called from run(), whose arguments are
        checked already)."""
        if self.nx == 0:
            X = self.prescribed(grid, p)[0]
            return (X, None, None) if summary else X
        lib, fast, kept = self.compiled(method), None, None
        if summary and grid[0] == 0.0 and c_summary.usable(self.dae, lib):
            t, t_addr = c_grid or (grid, None)
            X, st, values, code, note, kept = lib.run_summary(
                t, x0, p, rtol, atol, method, max_step, max_num_steps, checked=True, keep=True,
                t_addr=t_addr)
            fast = (values, code, note)
        else:
            X, st = lib.run(grid, x0, p, rtol, atol, method, max_step, max_num_steps)
        if not st.ok:
            raise compiled_failure(self.dae, grid, st)
        stats = st.stats or {"method": method}      # (the run's own dict, made for it)
        stats.pop("wall_time", None)
        self._last_stats = stats
        if kept is not None:
            X, states = self._kept_or_states(kept, grid)
            return X, fast, states
        # the driver refuses a solution that is not finite (RC_NOT_FINITE), so
        # a sum (a NaN or infinity anywhere makes it one) is all it takes here
        if not np.isfinite(np.add.reduce(X, axis=None)):
            self._check_finite(grid, X)
        return (X, fast, None) if summary else X

    def _kept_or_states(self, kept, grid):
        """(None, a function making the states when first read) of a kept
        run, whatever the size of its record: a summary alone never makes
        them (the library bounds the records it keeps, kept.py)."""
        return None, lambda: self._kept_states(kept, grid)

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
