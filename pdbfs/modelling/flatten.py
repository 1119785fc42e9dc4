"""Flattening: a component tree becomes one flat list of symbols and equations.

Every local symbol is renamed to its dotted path (``hammer.s``); connection
sets become equal across variables and a zero sum of flows (inside connectors
count +1, a composite's own connectors seen from inside count -1, as in
Modelica); a flange in no inside connection set gets zero force.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca

from .connectors import Flange, SignalInput
from pdbfs.errors import ConnectError, ModelError
from .symbols import der_of, time


@dataclass
class FlatParam:
    name: str
    sym: ca.SX
    decl: object          # symbols.Parameter
    value: object         # float, or SX expression of other FlatParam symbols


@dataclass
class FlatVar:
    name: str
    sym: ca.SX
    unit: str
    description: str
    is_state: bool
    start: object         # None, float or SX of parameter symbols
    output: bool
    rank: int             # preference to keep under alias elimination (higher keeps)
    der: ca.SX | None = None


@dataclass
class FlatSystem:
    name: str
    params: list[FlatParam] = field(default_factory=list)
    vars: list[FlatVar] = field(default_factory=list)
    equations: list[tuple[ca.SX, str]] = field(default_factory=list)
    events: list[tuple[ca.SX, str]] = field(default_factory=list)


def _join(prefix, name):
    return f"{prefix}.{name}" if prefix and name else (prefix or name)


def flatten(root) -> FlatSystem:
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
    local_eqs = [(comp, comp.equations(), comp.events()) for comp in root.walk()]
    for comp, eqs, _ in local_eqs:
        _check_balance(comp, sum(ca.SX(r).numel() for r in eqs))
    for comp in root.walk():
        prefix = comp.path()
        for p in comp._params.values():
            flat.params.append(FlatParam(_join(prefix, p.name), rename(p.sym, _join(prefix, p.name)),
                                         p.decl, p.value))
        for v in comp._vars.values():
            d = v.decl
            add_var(_join(prefix, v.name), v.sym, d.unit, d.description, d.is_state, d.start,
                    d.output or d.is_state, 2)
        for c in comp._connectors.values():
            for local_name, sym, unit, desc, _ in c.variables():
                add_var(_join(_join(prefix, c.name), local_name), sym, unit, desc, False, None,
                        False, 1)

    old_v, new_v = ca.vertcat(*old), ca.vertcat(*new)

    def glob(expr):
        if isinstance(expr, (int, float)):
            return float(expr)
        return ca.substitute(ca.SX(expr), old_v, new_v)

    for p in flat.params:
        if isinstance(p.value, ca.SX):
            p.value = glob(p.value)
    for v, start in deferred:
        v.start = None if start is None else glob(start)

    # component equations and events
    for comp, eqs, events in local_eqs:
        where = comp.label()
        for i, r in enumerate(eqs):
            r = ca.SX(r)
            for k in range(r.numel()):
                flat.equations.append((glob(r[k]), f"{where}, equation {i + 1}"))
        for expr, label in events:
            flat.events.append((glob(expr), _join(comp.path(), label)))

    _connection_equations(root, flat, glob)
    _check_time_not_shadowed(flat)
    _check_foreign_symbols(flat)
    return flat


def _connection_equations(root, flat, glob):
    inside = set()   # connectors that appear as inside members of some set
    for comp in root.walk():
        sets = _merge(comp._connections)
        for members in sets:
            signs = []
            for c in members:
                outside = c.owner is comp
                signs.append(-1.0 if outside else 1.0)
                if not outside:
                    inside.add(id(c))
            label = "connect(" + ", ".join(c.path() for c in members) + ")"
            first = members[0]
            if first.kind == "translational":
                for c in members[1:]:
                    flat.equations.append((glob(c.s - first.s), label))
                flat.equations.append((glob(sum(s * c.f for s, c in zip(signs, members))), label))
            else:
                outs = [c for c, s in zip(members, signs) if c.is_output == (s > 0)]
                if len(outs) > 1:
                    raise ConnectError(f"{label}: more than one signal source: "
                                       + ", ".join(c.path() for c in outs))
                if not outs:
                    raise ConnectError(f"{label}: no signal output drives these inputs")
                for c in members[1:]:
                    flat.equations.append((glob(c.value - first.value), label))
    for comp in root.walk():
        for c in comp._connectors.values():
            if id(c) in inside:
                continue
            if isinstance(c, Flange):
                flat.equations.append((glob(c.f), f"{c.path()} is unconnected: zero force"))
            elif isinstance(c, SignalInput) and comp is not root:
                raise ConnectError(f"signal input {c.path()} is not connected")


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


def _merge(connections):
    """Union connect() groups that share a connector into connection sets."""
    sets: list[list] = []
    for group in connections:
        hit = [s for s in sets if any(any(c is m for m in s) for c in group)]
        merged = [c for s in hit for c in s]
        for c in group:
            if not any(c is m for m in merged):
                merged.append(c)
        sets = [s for s in sets if not any(s is h for h in hit)] + [merged]
    return sets


def _check_time_not_shadowed(flat):
    for v in flat.vars:
        if v.name == "time":
            raise ModelError("a variable may not be called 'time'")
    flat.time = time


def _check_foreign_symbols(flat):
    """Every symbol in an equation must belong to this rig (or be time)."""
    known = {"time"} | {p.name for p in flat.params} | {v.name for v in flat.vars}
    known |= {f"der({v.name})" for v in flat.vars}
    for what, items in (("equation", flat.equations), ("event indicator", flat.events)):
        for expr, where in items:
            strangers = sorted({s.name() for s in ca.symvar(expr)} - known)
            if strangers:
                raise ModelError(
                    f"{where}: uses {', '.join(strangers)}, which belong(s) to no component of "
                    f"this rig (a variable of another rig, or a symbol made outside declare())")
