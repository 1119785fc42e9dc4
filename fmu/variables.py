"""What an FMU of a DAE exposes: its variables (value references,
causality, variability, units, bounds), the nominal values of its states and
its model structure (dependencies), derived from the DAE alone.

A rig's inputs (``dae.inputs``) are variables of causality ``input``: the
C writes each one's value and slope into the input entries that end ``p``
(``dae.input_rows()``); the outputs and derivatives list them among their
dependencies."""
from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from pdbfs.errors import ExportError
from pdbfs.modelling import DAE
from pdbfs.modelling.initialization import start_pattern
from pdbfs.native.codegen import FUNCTION_NAMES, model_functions
# solver.rtol's range, inclusive, declared and checked alike: the rule of every path
from pdbfs.native.tolerances import RTOL_MAX, RTOL_MIN

from . import units as _units
from .derivatives import derivative_functions, output_derivative_function

DEFAULT_MAX_NUM_STEPS = 10_000_000
#: solver.method's items (name, value, description): the pdbfs.SolverMethod type of
#: both FMI versions, the documentation's range and the C (fmu_instance.h METHOD_*)
SOLVER_METHODS = (
    ("auto", 0, "decided at initialisation from the parameters, the start and the stop time as in "
                "pdbfs's compiled backend: the cheapest method for the run by an estimate of its steps "
                "(from the modes of d(der(x))/dx at the start) and of a step's cost; without a stop time, "
                "the cheapest for each second of a long run. Where that is explicit Runge-Kutta or BDF, "
                "the run switches between the two at the solvers' own steps: to BDF where the explicit "
                "steps are held by stability, back at an event or where BDF's steps turn short"),
    ("BDF", 1, "CVODE backward differentiation formulas, Newton (exact sparse Jacobian, band or dense LU)"),
    ("Adams", 2, "CVODE Adams-Moulton (fixed point below 40 states, else Newton)"),
    ("ERK", 3, "explicit Runge-Kutta 8(5,3), Dormand and Prince, 7th-order dense output; roots of the "
               "event indicators located and the integration restarted there, a stop at each "
               "switch time"),
)
#: the declared min of a parameter that must be > 0: FMI's min is inclusive,
#: so the smallest normal double stands for "above 0" (0 and denormals are refused)
POSITIVE_MIN = 2.2250738585072014e-308


@dataclass
class _Var:
    name: str
    vr: int
    causality: str
    variability: str
    initial: str | None
    description: str
    type: str = "Real"
    start: float | int | None = None
    unit: str | None = None
    min: float | None = None
    max: float | None = None
    derivative: int | None = None   # 1-based index of the state
    declared_type: str | None = None
    nominal: float | None = None


def _deps(jac_sparsity: ca.Sparsity, cols_to_index: list[int | None]) -> list[list[int]]:
    """For each row of a Jacobian's pattern, the sorted indices of the
    columns it depends on (one pass over the nonzeros); a column whose index
    is None (an input's slope, t_ref: no variable) is left out."""
    out = [set() for _ in range(jac_sparsity.size1())]
    rows, cols = jac_sparsity.get_triplet()
    for r, c in zip(rows, cols):
        if cols_to_index[c] is not None:
            out[r].add(cols_to_index[c])
    return [sorted(o) for o in out]


def _check_dae(dae: DAE) -> None:
    if not dae.is_ode:
        raise ExportError(f"DAE '{dae.name}' has {dae.z.numel()} algebraic variable(s) "
                         f"({', '.join(dae.z_names)}): the FMU exporter needs a pure ODE; "
                         "simplify the rig so that no algebraic variable remains")
    if dae.x.numel() == 0:
        raise ExportError(f"DAE '{dae.name}' has no states: nothing to integrate")
    _check_inputs(dae)
    n_u = len(getattr(dae, "inputs", ()))
    for what, n, info in (("x", dae.x.numel(), dae.x_info), ("p", dae.p.numel() - (2 * n_u + 1 if n_u else 0),
                                                             dae.params), ("y", dae.y.numel(), dae.y_info)):
        if n != len(info):
            raise ExportError(f"DAE '{dae.name}': {what} has {n} entries but {len(info)} infos")
    if dae.events.numel() != len(dae.event_names):
        raise ExportError(f"DAE '{dae.name}': {dae.events.numel()} event indicators but "
                         f"{len(dae.event_names)} names")
    names = dae.p_names + dae.x_names + [n for n in dae.calculated] + dae.input_names
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ExportError(f"DAE '{dae.name}': duplicate names {sorted(dup)}")
    for n in names:
        if n.startswith("solver.") or n.startswith("der("):
            raise ExportError(f"DAE '{dae.name}': the name '{n}' is reserved by the FMU exporter")
    for prm in dae.params:
        v = prm.value
        if not math.isfinite(v) or (prm.positive and not v > 0) or \
                (prm.min is not None and v < prm.min) or (prm.max is not None and v > prm.max):
            raise ExportError(f"parameter {prm.name}: default {v} violates its own bounds")
    for n in dae.x_names:
        if n in dae.p_names:
            raise ExportError(f"'{n}' is both a state and a parameter")


def _check_inputs(dae: DAE) -> None:
    """Refuse an input the rig differentiates: an importer gives an input's
    value only (Model Exchange has no input derivatives; Co-Simulation holds
    an input over a step unless the importer sets its slope), so the
    derivative the equations use would be wrong."""
    rows = dae.input_rows()
    if rows is None:
        return
    # at t = t_ref each input is its value: a slope still there is its derivative, used
    eqs = ca.substitute(ca.vertcat(dae.ode, dae.y, dae.events), dae.t, dae.p[rows[2]])
    for k, name in enumerate(dae.input_names):
        if ca.depends_on(eqs, dae.p[rows[1] + k]):
            raise ExportError(f"rig {dae.name}: input {name} is differentiated (its rate enters the "
                              "equations, as a prescribed position's velocity does), but an FMU's "
                              "importer gives an input's value only; filter it (a FirstOrder or "
                              "SecondOrder block) or drive a force or pressure instead")


def input_spans(dae: DAE) -> list[tuple[float | None, float | None, float | None, list[str]]]:
    """Per input of the rig: (min, max, nominal, the signals that clamp it)
    from the signal inputs it drives directly (an entry of y that is the
    input itself, as a valve's ``valve.opening``): the range none of them
    clamps (the largest min, the smallest max), their nominal; without one,
    the magnitude of the input's start (None: 0)."""
    rows = dae.input_rows()
    out = []
    for k, u in enumerate(getattr(dae, "inputs", ())):
        expr = dae.p[rows[0] + k] + dae.p[rows[1] + k] * (dae.t - dae.p[rows[2]])
        lo = hi = nominal = None
        by = []
        for j, vi in enumerate(dae.y_info):
            span = getattr(vi, "span", (None, None, None))
            if span == (None, None, None) or not ca.is_equal(dae.y[j], expr, 3):
                continue
            if span[0] is not None:
                lo = span[0] if lo is None else max(lo, span[0])
            if span[1] is not None:
                hi = span[1] if hi is None else min(hi, span[1])
            if span[0] is not None or span[1] is not None:
                by.append(vi.name)
            nominal = nominal or span[2]
        if lo is not None and hi is not None and not lo < hi:
            raise ExportError(f"rig {dae.name}: input {u.name} drives {' and '.join(by)}, which clamp it to "
                              "ranges that do not overlap")
        if (lo is not None and u.start < lo) or (hi is not None and u.start > hi):
            raise ExportError(f"rig {dae.name}: input {u.name} starts at {u.start:g}, outside "
                              f"[{_bound(lo, '-inf')}, {_bound(hi, 'inf')}] where {' and '.join(by)} clamps it: "
                              "give it a start in that range")
        out.append((lo, hi, nominal or (abs(u.start) or None), by))
    return out


def _bound(v: float | None, none: str) -> str:
    return none if v is None else f"{v:g}"


def _reduced_start_parameters(dae: DAE) -> dict[str, list[str]]:
    """Parameter name -> the states index reduction made algebraic whose
    declared start it enters (their starts are checked, not free)."""
    out: dict[str, list[str]] = {}
    for name, _, expr in getattr(dae, "reduced_starts", None) or []:
        for sym in ca.symvar(expr):
            out.setdefault(sym.name(), []).append(name)
    return out


class FmuModel:
    """Everything derived from the DAE that the C header and the XML need."""

    def __init__(self, dae: DAE, ident: str, stop_time: float, step_size: float, tolerance: float):
        _check_dae(dae)
        self.dae, self.ident = dae, ident
        self.stop_time, self.step_size, self.tolerance = stop_time, step_size, tolerance
        #: modelDescription's version, author, license, copyright lines (rights.rights_attrs)
        self.rights: list[str] = []
        nx, npar = dae.x.numel(), len(dae.params)
        # np: all of p (the C's size); npar: the free parameters; nu: the inputs,
        # whose values, slopes and t_ref end p (u0, du0, t_ref = dae.input_rows())
        self.nx, self.np, self.npar = nx, dae.p.numel(), npar
        self.nu = len(getattr(dae, "inputs", ()))
        self.u_rows = dae.input_rows() or (npar, npar, npar)
        self.calc_names = list(dae.calculated)
        self.calc_expr = ca.vertcat(*[dae.calculated[n][0] for n in self.calc_names]) \
            if self.calc_names else ca.SX(0, 1)
        self.nc = len(self.calc_names)
        self.ne = dae.events.numel()
        self.ny = dae.y.numel()
        x_names, p_names = dae.x_names, dae.p_names
        taken = set(x_names) | set(p_names) | set(self.calc_names) | set(dae.input_names)
        # y entries that are states are served by the state variable itself;
        # ones named like a parameter or a calculated parameter are dropped
        self.y_alias_state: dict[int, int] = {}
        self.y_exposed: list[int] = []
        seen = set()
        for i, vi in enumerate(dae.y_info):
            if vi.name in x_names:
                self.y_alias_state[i] = x_names.index(vi.name)
            elif vi.name in taken or vi.name in seen:
                continue
            else:
                self.y_exposed.append(i)
                seen.add(vi.name)
        self.nyv = len(self.y_exposed)
        #: the exposed entries of y that are outputs (their time derivatives: pdbfs_yder)
        self.y_outputs = [i for i in self.y_exposed if dae.y_info[i].output]
        self.state_is_output = [False] * nx
        for i, k in self.y_alias_state.items():
            if dae.y_info[i].output:
                self.state_is_output[k] = True
        # value references
        self.vr_p = 0
        self.vr_rtol = npar
        self.vr_maxstep = npar + 1
        self.vr_c = npar + 2
        self.vr_x = self.vr_c + self.nc
        self.vr_dx = self.vr_x + nx
        self.vr_y = self.vr_dx + nx
        self.vr_u = self.vr_y + self.nyv          # the inputs (none: no value references)
        self.vr_method = self.vr_u + self.nu
        self.vr_maxnumsteps = self.vr_method + 1
        p0 = dae.p_default()
        x0 = np.array(dae.function("start")(p0), dtype=float).ravel()
        self.x_nominal = [1.0] * nx  # absolute tolerance = rtol * nominal
        for i, vi in enumerate(dae.x_info):
            try:
                exps, _ = _units.parse(vi.unit)
            except _units.UnitError:
                exps = {}
            scale = 1e-3 if exps.get("m", 0) >= 1 else 1.0  # positions: mm-level absolute accuracy scale
            self.x_nominal[i] = max(abs(float(x0[i])), scale) if np.isfinite(x0[i]) else 1.0
        self._build_variables()

    # -- CasADi functions -----------------------------------------------------
    def functions(self) -> list[ca.Function]:
        """The CasADi functions the FMU's C code is generated from: the model's and its derivatives'."""
        return model_functions(self.dae, FUNCTION_NAMES, self.calc_expr) + \
            derivative_functions(self.dae, self.y_exposed) + [output_derivative_function(self.dae, self.y_outputs)]

    # -- variables --------------------------------------------------------------
    def _build_variables(self) -> None:
        d = self.dae
        V: list[_Var] = []
        starts_of = _reduced_start_parameters(d)
        for k, prm in enumerate(d.params):
            lo = prm.min
            if prm.positive:
                lo = POSITIVE_MIN if lo is None else max(lo, POSITIVE_MIN)
            desc = prm.description + (" (must be > 0)" if prm.positive else "")
            if prm.name in starts_of:
                desc += (f"; gives the start of {', '.join(starts_of[prm.name])}, which index reduction "
                         f"computes from {'; '.join(d.reduced_by)}: checked against it at initialisation")
            V.append(_Var(prm.name, self.vr_p + k, "parameter", "tunable" if prm.tunable else "fixed", "exact",
                          desc, start=prm.value, unit=prm.unit, min=lo, max=prm.max))
        V.append(_Var("solver.rtol", self.vr_rtol, "parameter", "fixed", "exact",
                      "Co-Simulation: the solver's relative tolerance; if not set, fmi2SetupExperiment's tolerance "
                      "is used when given. Absolute tolerance = rtol * nominal of each state",
                      start=self.tolerance, unit="1", min=RTOL_MIN, max=RTOL_MAX))
        V.append(_Var("solver.max_step", self.vr_maxstep, "parameter", "fixed", "exact",
                      "Co-Simulation: maximum internal solver step (0: no limit)", start=0.0, unit="s", min=0.0))
        V.append(_Var("solver.method", self.vr_method, "parameter", "fixed", "exact",
                      "Co-Simulation: integration method, 0 = auto (decided at initialisation: "
                      "explicit Runge-Kutta where the rig is not stiff over the run, else CVODE), "
                      "1 = CVODE BDF, 2 = CVODE Adams, 3 = explicit Runge-Kutta 8(5,3)",
                      type="Enumeration", start=0, declared_type="pdbfs.SolverMethod"))
        V.append(_Var("solver.max_num_steps", self.vr_maxnumsteps, "parameter", "fixed", "exact",
                      "Co-Simulation: most internal solver steps in one fmi2DoStep (more is a solver failure)",
                      type="Integer", start=DEFAULT_MAX_NUM_STEPS, min=1))
        self.input_spans = input_spans(d)
        for k, (u, (lo, hi, nominal, by)) in enumerate(zip(getattr(d, "inputs", ()), self.input_spans)):
            desc = (u.description or f"input {u.name}") + \
                (f" ({' and '.join(by)} clamps it to [{_bound(lo, '-inf')}, {_bound(hi, 'inf')}])" if by else "")
            V.append(_Var(u.name, self.vr_u + k, "input", "continuous", None, desc, start=u.start, unit=u.unit,
                          min=lo, max=hi, nominal=nominal))
        p_tunable = [prm.tunable for prm in d.params]
        cols = list(range(self.npar)) + [None] * (self.np - self.npar)   # the parameters only
        jc = _deps(ca.jacobian_sparsity(self.calc_expr, d.p), cols) if self.nc else None
        for k, n in enumerate(self.calc_names):
            vi = d.calculated[n][1]
            dep = jc[k]
            tun = any(p_tunable[j] for j in dep)
            V.append(_Var(n, self.vr_c + k, "calculatedParameter", "tunable" if tun else "fixed", "calculated",
                          vi.description, unit=vi.unit))
        for k, vi in enumerate(d.x_info):
            V.append(_Var(vi.name, self.vr_x + k, "output" if self.state_is_output[k] else "local",
                          "continuous", "calculated", vi.description, unit=vi.unit,
                          nominal=self.x_nominal[k]))
        known = {}  # a derivative's unit is named like a unit the rig already uses, if any
        for u in [prm.unit for prm in d.params] + [vi.unit for vi in d.x_info + d.y_info]:
            try:
                e, f = _units.parse(u)
                known.setdefault((tuple(e.values()), f), u)
            except _units.UnitError:
                pass

        def dunit(u):
            du = _units.per_second(u)
            try:
                e, f = _units.parse(du)
                return known.get((tuple(e.values()), f), du)
            except _units.UnitError:
                return du
        for k, vi in enumerate(d.x_info):
            V.append(_Var(f"der({vi.name})", self.vr_dx + k, "local", "continuous", "calculated",
                          f"time derivative of {vi.name}", unit=dunit(vi.unit), derivative=None))
        for k, yi in enumerate(self.y_exposed):
            vi = d.y_info[yi]
            V.append(_Var(vi.name, self.vr_y + k, "output" if vi.output else "local", "continuous",
                          "calculated", vi.description, unit=vi.unit))
        # sort by value reference (the method enum goes last) and index from 1
        V.sort(key=lambda v: v.vr)
        self.vars = V
        self.index = {v.name: i + 1 for i, v in enumerate(V)}
        self.param_vars = [V[self.index[n] - 1] for n in d.p_names]
        x_idx = [self.index[n] for n in d.x_names]
        for k, vi in enumerate(d.x_info):
            V[self.index[f"der({vi.name})"] - 1].derivative = x_idx[k]
        self.x_index = x_idx

    # -- model structure --------------------------------------------------------
    def structure(self):
        """(outputs, derivatives, initial unknowns) with their dependencies;
        computed once (modelDescription.xml is written twice: for the GUID)."""
        if getattr(self, "_structure", None) is None:
            self._structure = self._find_structure()
        return self._structure

    def _find_structure(self):
        d = self.dae
        x_idx = self.x_index
        u_idx = [self.index[n] for n in d.input_names]
        # p's columns: the parameters and the inputs' values are variables (the slopes and t_ref are not)
        p_idx = [self.index[n] for n in d.p_names] + u_idx + [None] * (self.np - self.npar - self.nu)
        # outputs and derivatives depend on states and inputs
        known = ca.vertcat(d.x, d.p[self.u_rows[0]:self.u_rows[0] + self.nu])
        jy = _deps(ca.jacobian_sparsity(d.y, known), x_idx + u_idx)
        jf = _deps(ca.jacobian_sparsity(d.ode, known), x_idx + u_idx)
        outputs = []  # (index, deps)
        for k in range(self.nx):
            if self.state_is_output[k]:
                outputs.append((x_idx[k], [x_idx[k]]))
        for k, yi in enumerate(self.y_exposed):
            if d.y_info[yi].output:
                outputs.append((self.index[d.y_info[yi].name], jy[yi]))
        outputs.sort()
        derivs = [(self.index[f"der({n})"], jf[k]) for k, n in enumerate(d.x_names)]
        # initial unknowns: dependencies on the parameters, with x = x0(p)
        x0 = start_pattern(d)  # a solved start depends on what its equations use
        sub = lambda e: ca.substitute(e, d.x, x0)  # noqa: E731
        init = []
        jx0 = _deps(ca.jacobian_sparsity(x0, d.p), p_idx)
        jy0 = _deps(ca.jacobian_sparsity(sub(d.y), d.p), p_idx)
        jf0 = _deps(ca.jacobian_sparsity(sub(d.ode), d.p), p_idx)
        for k in range(self.nx):
            init.append((x_idx[k], jx0[k]))
            init.append((self.index[f"der({d.x_names[k]})"], jf0[k]))
        for k, yi in enumerate(self.y_exposed):
            if d.y_info[yi].output:
                init.append((self.index[d.y_info[yi].name], jy0[yi]))
        if self.nc:
            jc = _deps(ca.jacobian_sparsity(self.calc_expr, d.p), p_idx)
            for k, n in enumerate(self.calc_names):
                init.append((self.index[n], jc[k]))
        init.sort()
        return outputs, derivs, init

    # -- modelDescription.xml ---------------------------------------------------
