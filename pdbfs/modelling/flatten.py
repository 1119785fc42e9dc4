"""Flattening: a component tree becomes one flat list of symbols and equations.

Every local symbol is renamed to its dotted path (``hammer.s``); connection
sets become equal across variables and a zero sum of flows (inside connectors
count +1, a composite's own connectors seen from inside count -1, as in
Modelica), for every physical domain alike (a connector names its across
and through variables); a flange in no inside connection set gets zero
force, a hydraulic port zero flow (closed) and a heat port zero heat flow
(insulated) where its component allows it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from .connectors import Flange, HeatPort, HydraulicPort, SignalInput
from pdbfs.errors import ConnectError, ModelError
from .rig_inputs import T_REF, input_name
from .symbols import der_of, time


@dataclass
class FlatParam:
    """A parameter of the flat system, under its dotted name."""

    name: str
    sym: ca.SX
    decl: object          # symbols.Parameter
    value: object         # float, or SX expression of other FlatParam symbols


@dataclass
class FlatVar:
    """A variable of the flat system, under its dotted name."""

    name: str
    sym: ca.SX
    unit: str
    description: str
    is_state: bool
    start: object         # None, float or SX of parameter symbols
    output: bool
    rank: int             # preference to keep under alias elimination (higher keeps)
    der: ca.SX | None = None
    fixed: bool = True    # start is fixed (False: a guess, solved at initialization)
    limits: tuple = (None, None, "")   # (min, max, beyond) of the declaration
    span: tuple = (None, None, None)   # (min, max, nominal) a SignalInput declares (clamped beyond)


@dataclass
class FlatInput:
    """One input of the rig, flattened: u(t) = value + slope * (t - t_ref) over a segment."""

    name: str             # the input's name: its component's dotted path
    value: ca.SX          # its value at the segment's start t_ref (named like the input)
    slope: ca.SX          # its slope over the segment (named der(name))
    decl: object          # rig_inputs.RigInput: unit, description, start


@dataclass
class FlatSystem:
    """The whole rig flattened: parameters, variables and equations, before simplification."""

    name: str
    params: list[FlatParam] = field(default_factory=list)
    vars: list[FlatVar] = field(default_factory=list)
    equations: list[tuple[ca.SX, str]] = field(default_factory=list)
    events: list[tuple[ca.SX, str]] = field(default_factory=list)
    initial: list[tuple[ca.SX, str]] = field(default_factory=list)   # initial equations
    # physical consistency of the parameters: expression >= 0, (where, text, names)
    conditions: list = field(default_factory=list)
    # switch times known in advance (expressions of parameters): time events
    time_events: list[tuple[ca.SX, str]] = field(default_factory=list)
    event_text: dict[str, str] = field(default_factory=dict)   # event name -> what it marks
    inputs: list[FlatInput] = field(default_factory=list)     # the rig's inputs (rig_inputs.py)


def _join(prefix, name):
    return f"{prefix}.{name}" if prefix and name else (prefix or name)


def flatten(root) -> FlatSystem:
    """The component tree of ``root`` as one flat system: every variable and
    parameter under its dotted name, the connection equations added."""
    flat = FlatSystem(name=type(root).__name__)
    old, new = [], []          # local symbol -> global symbol
    deferred = []              # (FlatVar, local start) resolved after renaming

    def rename(local, name):
        g = ca.SX.sym(name)
        old.append(local)
        new.append(g)
        return g

    def add_var(name, local, unit, desc, is_state, start, output, rank):
        v = FlatVar(name, rename(local, name), unit, desc, is_state, None, output, rank)
        d = der_of(local)
        if d is not None:
            v.der = rename(d, f"der({name})")
        flat.vars.append(v)
        deferred.append((v, start))
        return v

    # equations first: der() calls in them create the derivative symbols
    local_eqs = [(comp, [r if isinstance(r, ca.SX) else ca.SX(r) for r in comp.equations()],
                  comp.events(), comp.time_events()) for comp in root.walk()]
    for comp, eqs, _, _ in local_eqs:
        _check_balance(comp, sum(r.numel() for r in eqs))
    local_init = [(comp, [r if isinstance(r, ca.SX) else ca.SX(r)
                          for r in comp.initial_equations()]) for comp in root.walk()]
    for comp in root.walk():
        prefix = comp.path()
        for p in comp._params.values():
            flat.params.append(FlatParam(_join(prefix, p.name), rename(p.sym, _join(prefix, p.name)),
                                         p.decl, p.value))
        for v in comp._vars.values():
            d = v.decl
            fv = add_var(_join(prefix, v.name), v.sym, d.unit, d.description, d.is_state,
                         d.start, d.output or d.is_state, 2)
            fv.fixed = getattr(d, "fixed", True)
            fv.limits = (getattr(d, "min", None), getattr(d, "max", None), getattr(d, "beyond", ""))
        for attr, slot in comp._inputs.items():
            name = input_name(comp, attr)
            flat.inputs.append(FlatInput(name, rename(slot.value, name),
                                         rename(slot.slope, f"der({name})"), slot.decl))
        # a signal output of a block or sensor at the rig's top level is an output
        # of the rig (an FMU's output, another model's input); an Input's is the input
        shown = comp._parent is root and not getattr(comp, "rig_input", False)
        for c in comp._connectors.values():
            for local_name, sym, unit, desc, _ in c.variables():
                fv = add_var(_join(_join(prefix, c.name), local_name), sym, unit, desc, False, None,
                             shown and getattr(c, "is_output", False), 1)
                fv.span = getattr(c, "span", fv.span)

    # every expression is renamed in one substitution (one per expression
    # would make flattening quadratic in the size of the rig)
    later = _Later()
    for p in flat.params:
        if isinstance(p.value, ca.SX):
            later.add(p.value, lambda e, p=p: setattr(p, "value", e))
    for v, start in deferred:
        if start is not None:
            later.add(start, lambda e, v=v: setattr(v, "start", e))

    # component equations and events
    for comp, eqs, events, times in local_eqs:
        where = comp.label()
        for expr, label, *text in times:
            later.equation(flat.time_events, expr, _join(comp.path(), label))
            if text:
                flat.event_text[_join(comp.path(), label)] = text[0]
        for expr, text, names in comp.conditions():
            later.equation(flat.conditions, expr if isinstance(expr, ca.SX) else ca.SX(expr),
                           (comp.label(), text, [_join(comp.path(), n) for n in names]))
        for i, r in enumerate(eqs):
            for rk in (ca.vertsplit(ca.vec(r), 1) if r.numel() > 1 else [r]):
                later.equation(flat.equations, rk, f"{where}, equation {i + 1}")
        for expr, label, *text in events:
            later.equation(flat.events, expr, _join(comp.path(), label))
            if text:
                flat.event_text[_join(comp.path(), label)] = text[0]

    for comp, eqs in local_init:
        for i, r in enumerate(eqs):
            for rk in (ca.vertsplit(ca.vec(r), 1) if r.numel() > 1 else [r]):
                later.equation(flat.initial, rk, f"{comp.label()}, initial equation {i + 1}")

    _connection_equations(root, flat, later)
    later.apply(ca.vertcat(*old), ca.vertcat(*new))
    _check_time_not_shadowed(flat)
    _check_foreign_symbols(flat)
    return flat


class _Later:
    """Expressions to rename, and where each result goes."""

    def __init__(self):
        self.exprs, self.puts = [], []

    def add(self, expr, put):
        if isinstance(expr, (int, float)):
            put(float(expr))
            return
        self.exprs.append(expr if isinstance(expr, ca.SX) else ca.SX(expr))
        self.puts.append(put)

    def equation(self, target, expr, where):
        """Append (renamed expr, where) to target, in this order."""
        target.append(None)
        k = len(target) - 1
        self.add(expr, lambda e, k=k: target.__setitem__(k, (e, where)))

    def apply(self, old, new):
        if not self.exprs:
            return
        scalar = all(e.is_scalar() for e in self.exprs)
        flat = ca.substitute(ca.vertcat(*(self.exprs if scalar else [ca.vec(e) for e in self.exprs])),
                             old, new)
        if scalar:                       # the usual case: one element each
            for v, put in zip(ca.vertsplit(flat, 1), self.puts):
                put(v)
            return
        k = 0
        for e, put in zip(self.exprs, self.puts):
            n = e.numel()
            put(ca.reshape(flat[k:k + n], e.shape) if e.shape != (1, 1) else flat[k])
            k += n


def _connection_equations(root, flat, later):
    """Equal across variables and a zero sum of flows per connection set, made
    in bulk (one subtraction, one sparse product) in the order of the sets."""
    inside = set()   # connectors that appear as inside members of some set
    same, flows = [], []   # (slot, a, b): a - b; (slot, [(sign, flow)])
    for comp in root.walk():
        for members in _merge(comp._connections):
            signs = []
            for c in members:
                outside = c.owner is comp
                signs.append(-1.0 if outside else 1.0)
                if not outside:
                    inside.add(id(c))
            label = "connect(" + ", ".join(c.path() for c in members) + ")"
            first = members[0]
            if first.kind != "signal":
                across, through = first.across, first.through
                for c in members[1:]:
                    same.append((_slot(flat.equations, label), getattr(c, across),
                                 getattr(first, across)))
                flows.append((_slot(flat.equations, label),
                              list(zip(signs, (getattr(c, through) for c in members)))))
            else:
                outs = [c for c, s in zip(members, signs) if c.is_output == (s > 0)]
                if len(outs) > 1:
                    raise ConnectError(f"{label}: more than one signal source: "
                                       + ", ".join(c.path() for c in outs))
                if not outs:
                    raise ConnectError(f"{label}: no signal output drives these inputs")
                for c in members[1:]:
                    same.append((_slot(flat.equations, label), c.value, first.value))
    if same:
        diff = ca.vertsplit(ca.vertcat(*[a for _, a, _ in same]) - ca.vertcat(*[b for _, _, b in same]), 1)
        for (slot, _, _), e in zip(same, diff):
            later.add(e, slot)
    if flows:
        syms, index, rows, cols, vals = [], {}, [], [], []
        for r, (_, terms) in enumerate(flows):
            for sign, f in terms:
                k = index.setdefault(f.element_hash(), len(syms))
                if k == len(syms):
                    syms.append(f)
                rows.append(r)
                cols.append(k)
                vals.append(sign)
        from scipy.sparse import csc_matrix
        M = ca.DM(csc_matrix((vals, (rows, cols)), shape=(len(flows), len(syms))))
        sums = ca.vertsplit(ca.mtimes(M, ca.vertcat(*syms)), 1)
        for (slot, _), e in zip(flows, sums):
            later.add(e, slot)
    for comp in root.walk():
        for c in comp._connectors.values():
            if id(c) in inside:
                continue
            if isinstance(c, Flange):
                later.equation(flat.equations, c.f, f"{c.path()} is unconnected: zero force")
            elif isinstance(c, HydraulicPort):
                if not c.closable:
                    raise ConnectError(
                        f"hydraulic port {c.path()} of {comp.label()} is not connected; an open "
                        "port is closed (zero flow) only on chambers and tanks, which makes no "
                        "sense here: connect it (e.g. to a Tank)")
                later.equation(flat.equations, c.q, f"{c.path()} is unconnected: closed, zero flow")
            elif isinstance(c, HeatPort):
                if not c.insulable:
                    raise ConnectError(
                        f"heat port {c.path()} of {comp.label()} is not connected; connect it "
                        "(e.g. to a HeatCapacitor or a FixedTemperature), or build the "
                        "component without its heat port")
                later.equation(flat.equations, c.Q_flow,
                               f"{c.path()} is unconnected: insulated, zero heat flow")
            elif isinstance(c, SignalInput) and comp is not root:
                raise ConnectError(f"signal input {c.path()} is not connected")


def _slot(target, where):
    """Reserve the next place in target; the returned setter fills it."""
    target.append(None)
    k = len(target) - 1
    return lambda e: target.__setitem__(k, (e, where))


def _check_balance(comp, n_eq):
    """Modelica's local balance: a leaf component has as many equations as
    unknowns minus its flange forces and inputs (those come from connections);
    a composite has one equation per variable it declares itself."""
    own = list(comp._vars)
    if comp._children:
        need, what = len(own), f"its own variables ({', '.join(own) or 'none'})"
    else:
        n_conn = sum(len(c.variables()) for c in comp._connectors.values())
        n_given = sum(1 for c in comp._connectors.values() for *_, flow in c.variables() if flow)
        n_given += sum(1 for c in comp._connectors.values() if isinstance(c, SignalInput))
        need = len(own) + n_conn - n_given
        what = (f"{len(own)} variables ({', '.join(own) or 'none'}) + {n_conn} connector "
                f"variables - {n_given} given by connections")
    if n_eq != need:
        kind = "under" if n_eq < need else "over"
        raise ModelError(f"component {comp.label()} is {kind}-determined: {n_eq} equations "
                         f"for {need} unknowns: {what}")


class _Set:
    __slots__ = ("stamp", "members")

    def __init__(self, stamp, members):
        self.stamp, self.members = stamp, members


def _merge(connections):
    """Union connect() groups that share a connector into connection sets, in
    the order of their last connect() (members: earlier sets first). A group
    that touches one set grows it in place, so a frame connected to
    thousands of parts costs no more than its connections."""
    set_of = {}                          # connector id -> _Set
    for stamp, group in enumerate(connections):
        hit = sorted({id(set_of[id(c)]): set_of[id(c)] for c in group if id(c) in set_of}.values(),
                     key=lambda st: st.stamp)
        if len(hit) == 1:
            target = hit[0]
        else:
            target = _Set(stamp, [c for st in hit for c in st.members])
            for c in target.members:
                set_of[id(c)] = target
        target.stamp = stamp
        for c in group:
            if id(c) not in set_of:
                set_of[id(c)] = target
                target.members.append(c)
    unique = {id(st): st for st in set_of.values()}
    return [st.members for st in sorted(unique.values(), key=lambda st: st.stamp)]


def _check_time_not_shadowed(flat):
    for v in flat.vars:
        if v.name == "time":
            raise ModelError("a variable may not be called 'time'")
    flat.time = time


def _check_foreign_symbols(flat):
    """Every symbol in an equation must belong to this rig (or be time)."""
    known = {"time"} | {p.name for p in flat.params} | {v.name for v in flat.vars}
    known |= {f"der({v.name})" for v in flat.vars}
    known |= {T_REF.name()} | {s.name() for i in flat.inputs for s in (i.value, i.slope)}
    _check_time_events(flat)
    exprs = [e for e, _ in flat.equations] + [e for e, _ in flat.events]
    if not exprs or not {s.name() for s in ca.symvar(ca.vertcat(*exprs))} - known:
        return                           # the usual case, found in one pass
    for expr, where in flat.equations + flat.events:      # name the first culprit
        strangers = sorted({s.name() for s in ca.symvar(expr)} - known)
        if strangers:
            raise ModelError(
                f"{where}: uses {', '.join(strangers)}, which belong(s) to no component of "
                f"this rig (a variable of another rig, or a symbol made outside declare())")


def _check_time_events(flat):
    """A time event is a time known before the run: parameters only."""
    params = {p.name for p in flat.params}
    for expr, where in flat.time_events:
        others = sorted({s.name() for s in ca.symvar(expr)} - params)
        if others:
            raise ModelError(f"time event {where}: depends on {', '.join(others)}; a time "
                             "event must be a time known in advance (parameters only)")
