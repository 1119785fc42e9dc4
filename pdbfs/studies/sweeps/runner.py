"""One chunk of sweep points, evaluated: the same code runs in this process,
in threads, in forked processes and on Dask workers.

With the compiled backend a chunk is one call of the summary driver (C:
integration and summary of every point, no Python object per point);
otherwise each point is simulated and summarised in Python (the CasADi
backend, start-value overrides, kept trajectories, and summary roles the C
driver does not know, such as the repeated blows of the drop rig).
"""
from __future__ import annotations

import hashlib
import json
import pickle
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.modelling import check_value, within_limits
from pdbfs.modelling.passes import reduced_start
from pdbfs.simulation import Simulator
from pdbfs.simulation.run.driven import run_driven
from pdbfs.simulation.results.summary import keys_for, summarize
from pdbfs.simulation.setup.initialize import needs_solving

#: list-valued summary entries (one value per blow) are stored as JSON text; the
#: blows' count is a column of its own (impact_count). tests/test_every_rig_studies.py
#: checks that every list a rig's summary holds is named here
LIST_KEYS = ("impact_times", "impact_peak_pressures", "impact_durations")


@dataclass(frozen=True)
class Settings:
    """The settings every point of a sweep runs with (times in s)."""

    t_end: float = 0.02
    n_out: int = 2001
    rtol: float = 1e-8
    atol: float = 1e-10
    method: str = "adams"
    max_step: float | None = None
    backend: str = "auto"
    start: tuple = ()                 # (name, value) pairs overriding start values
    trajectories: bool = False


@dataclass
class Chunk:
    """The evaluated points of one chunk, as columns."""

    index: np.ndarray                 # point numbers
    params: np.ndarray                # len(index) x len(names)
    summary: dict                     # key -> float array (NaN: undefined) or list of JSON text
    error: list                       # "" or "Type: message", per point
    results: list = field(default_factory=list)   # Results, with trajectories=True


class Runner:
    """Evaluates blocks of points of ``names`` for one rig and settings."""

    def __init__(self, sim: Simulator, names, fixed: dict, settings: Settings, inputs=None):
        dae = sim.dae
        self.sim, self.names, self.settings = sim, list(names), settings
        self.inputs = inputs            # the rig's inputs (inputs.SweepInputs), or None
        swept = inputs.dims if inputs is not None else {}
        # the parameters among the names: their columns in the block and in p
        self.pcols = [k for k, n in enumerate(self.names) if n not in swept]
        self.columns = [dae.p_names.index(self.names[k]) for k in self.pcols]
        self.infos = [dae.params[i] for i in self.columns]
        self.base = sim.param_vector(fixed)
        self.keys = keys_for(dae)
        self.fast = None
        # the compiled batch starts from the declared starts: not for a solved start,
        # nor for inputs that are traces (a run with inputs, segment by segment)
        if settings.backend == "c" and not settings.start and not settings.trajectories \
                and not needs_solving(dae, None) and (inputs is None or inputs.constant):
            lib = sim.compiled(settings.method)
            if set(self.keys) <= set(lib.summary_keys):
                self.fast = lib

    def run(self, index, block) -> Chunk:
        """Evaluate the points ``block`` (rows of parameter values) numbered ``index``."""
        block = np.atleast_2d(np.asarray(block, dtype=float))
        n = block.shape[0]
        P = np.repeat(self.base[None, :], n, axis=0)
        P[:, self.columns] = block[:, self.pcols]
        if self.inputs is not None and self.inputs.constant:
            self.inputs.set_constants(P, self.names, block)
        error = [""] * n
        # each value within its parameter's limits and the components' conditions
        # held, checked a column (a chunk) at a time; a point refused is looked at
        # alone below, for the message naming what is wrong
        fine = np.ones(n, dtype=bool)
        for j, info in zip(self.pcols, self.infos):
            fine &= within_limits(block[:, j], info)
        if fine.any():
            fine[fine] = self.sim.dae.conditions_hold(P[fine])
        alone = np.flatnonzero(~fine)
        if getattr(self.sim.dae, "reduced_starts", None):
            alone = range(n)        # a start index reduction computes is checked per point
        for i in alone:
            for j, info in zip(self.pcols, self.infos):
                try:
                    check_value(block[i, j], info.name, info)
                except ParameterError as err:
                    error[i] = f"ParameterError: {err}"
                    break
            else:
                try:                # the components' physical consistency, per point
                    self.sim.dae.check_conditions(P[i])
                    if getattr(self.sim.dae, "reduced_starts", None):
                        # a start index reduction computes is not free
                        reduced_start.check(self.sim.dae, P[i], ParameterError)
                except ParameterError as err:
                    error[i] = f"ParameterError: {err}"
        ok = np.array([not e for e in error])
        summary = {k: ([""] * n if k in LIST_KEYS else np.full(n, np.nan)) for k in self.keys}
        results = [None] * n if self.settings.trajectories else []
        if self.fast is not None:
            self._run_fast(P, ok, summary, error, block)
        else:
            self._run_points(P, ok, summary, error, results, block)
        return Chunk(np.asarray(index), block, summary, error, results)

    def _run_fast(self, P, ok, summary, error, block):
        s = self.settings
        from pdbfs.simulation.run.compiled import RC_FOLLOW, SUMMARY_KEYS
        from pdbfs.simulation.setup import limits
        values, codes, messages = self.fast.summaries(P[ok], s.t_end, s.rtol, s.atol, s.method,
                                                      s.max_step)
        rows = np.flatnonzero(ok)
        for k in self.keys:
            summary[k][rows] = values[:, SUMMARY_KEYS.index(k)]
        same_as_result_summary(summary, rows)
        codes = np.asarray(codes)
        for r, code, msg in zip(rows, codes, messages):
            if code and code != RC_FOLLOW:
                bound = limits.from_c(self.sim.dae, msg) if code == limits.RC_LIMIT else None
                error[r] = f"SolverError: {bound}" if bound else \
                    f"SolverError: rig {self.sim.dae.name}: {msg or f'failed (code {code})'}"
                for k in self.keys:
                    summary[k][r] = np.nan
        # a pulse running at t_end: whether its highest pressure so far is its peak
        # shows only past the horizon. The driver follows it there with the explicit
        # method; with CVODE's, and where that failed, Result.summary follows it
        late = np.zeros(len(ok), dtype=bool)
        late[rows] = codes == RC_FOLLOW
        if "complete" in summary and s.method != "erk":
            late[rows] |= (codes == 0) & (summary["complete"][rows] == 0)
        if late.any():
            self._run_points(P, late, summary, error, {}, block)

    def _run_points(self, P, ok, summary, error, results, block):
        s = self.settings
        for i in np.flatnonzero(ok):
            try:
                args = dict(params=dict(zip(self.sim.dae.p_names, P[i])),
                            start=dict(s.start) or None, rtol=s.rtol, atol=s.atol,
                            method=s.method, max_step=s.max_step, backend=s.backend)
                if self.inputs is None:
                    res = self.sim.run(s.t_end, s.n_out, **args)
                else:               # this point's inputs: a run segment by segment
                    res = run_driven(self.sim, self.inputs.of_point(self.names, block[i]),
                                     s.t_end, s.n_out, **args)
                # the complete column says it per point: no warnings (catch_warnings is
                # process-wide, not per thread: the sweep's threads would let them through)
                out = summarize(res, warn=False)
            except PdbfsError as err:
                error[i] = f"{type(err).__name__}: {err}"
                continue
            except (ArithmeticError, ValueError, RuntimeError) as err:   # anything the summary hits
                if "KeyboardInterrupt" in str(err):      # Ctrl-C inside CasADi: stop, not a point
                    raise KeyboardInterrupt from None
                error[i] = f"{type(err).__name__}: {err}"
                continue
            for k in self.keys:
                v = out.get(k)
                if k in LIST_KEYS:
                    summary[k][i] = json.dumps(v) if v is not None else ""
                else:
                    summary[k][i] = np.nan if v is None else float(v)
            if s.trajectories:
                results[i] = res


def same_as_result_summary(summary, rows):
    """The C driver's values under Result.summary()'s rules: a pulse that did
    not end inside the run has no duration and no restitution; no pulse, no
    time of peak."""
    if "complete" in summary:
        cut = rows[summary["complete"][rows] == 0]
        for k in ("pulse_duration", "restitution_coefficient"):
            if k in summary:
                summary[k][cut] = np.nan
    if "peak_pressure" in summary and "time_of_peak" in summary:
        none = rows[~(summary["peak_pressure"][rows] > 0)]
        summary["time_of_peak"][none] = np.nan


# -------------------------------------------------------- on Dask workers
def payload(sim: Simulator, names, fixed, settings: Settings, inputs=None) -> tuple[str, bytes]:
    """What a worker needs to build the Runner: the DAE (CasADi's pickling),
    the swept names, the fixed values, the settings and the inputs (their
    checked traces); and a key for it."""
    ins = None if inputs is None else (inputs.fixed, inputs.dims)
    with ca.global_pickle_context():
        data = pickle.dumps((sim.dae, list(names), dict(fixed), settings, ins))
    return hashlib.sha256(data).hexdigest()[:24], data


_RUNNERS: dict = {}   # key -> Runner, per worker process: the rig is built once per worker


def run_remote(key: str, data: bytes, index, block) -> Chunk:
    """Runner.run on a Dask worker, its Runner built from ``data`` (payload()) once per process."""
    runner = _RUNNERS.get(key)
    if runner is None:
        with ca.global_unpickle_context():
            dae, names, fixed, settings, ins = pickle.loads(data)
        from .inputs import SweepInputs
        inputs = None if ins is None else SweepInputs(dae, *ins)
        runner = _RUNNERS[key] = Runner(Simulator.of(dae), names, fixed, settings, inputs)
    return runner.run(index, block)
