"""Component: parameters, variables, connectors, children and equations.

A component class declares ``Parameter`` class attributes, and in
``declare()`` its connectors, variables and sub-components (by assigning them
to attributes); ``equations()`` returns residual expressions. A rig is a
component whose children are connected with ``connect()``; it may itself be
used inside a bigger rig.
"""
from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

import numbers

import casadi as ca
import numpy as np

from pdbfs.errors import ConnectError, ModelError, ParameterError, plain

from .connectors import Connector, signal_unit
from .rig_inputs import InputSlot, RigInput
from .symbols import Parameter, Variable, described

if TYPE_CHECKING:
    from .dae import DAE


class ParamSlot:
    """A parameter of one component instance: declaration, symbol and value
    (a number, or a CasADi expression of other parameters' symbols)."""

    def __init__(self, decl: Parameter, name: str, value):
        self.decl = decl
        self.name = name
        self.sym = ca.SX.sym(name)
        self.value = value


class VarSlot:
    """A variable of one component instance: declaration and symbol."""

    def __init__(self, decl: Variable, name: str):
        self.decl = decl
        self.name = name
        self.sym = ca.SX.sym(name)


class Component:
    """Base class of every component and rig.

    A component class declares ``Parameter`` class attributes; in
    ``declare()`` its connectors, variables and sub-components (assigned to
    attributes); in ``equations()`` its residuals. The component library
    (``pdbfs.components``) and the rigs (``pdbfs.models``) are built this
    way; the tutorial on building a rig shows one from scratch.

    Parameters
    ----------
    **values : float or casadi.SX
        Values of the declared parameters by name, SI units
        (``Mass(m=250.0)``): a number, or an expression of other parameters'
        symbols. A parameter not given keeps its declared default.

    Raises
    ------
    pdbfs.ParameterError
        For a name the component does not declare, or a value that is not a
        number within the declaration's bounds.
    """

    #: how the component bounds an oil circuit's pressures (modelling.pressure_bound):
    #: None, it may raise one above every source's
    pressure_bound: dict | None = None

    def __init__(self, **values: float | ca.SX):
        set_ = object.__setattr__
        set_(self, "_name", "")
        set_(self, "_parent", None)
        set_(self, "_params", {})
        set_(self, "_vars", {})
        set_(self, "_inputs", {})       # at most one RigInput (rig_inputs.py)
        set_(self, "_connectors", {})
        set_(self, "_children", {})
        set_(self, "_connections", [])
        set_(self, "_compiled", None)
        # numbers given by the caller: a parameter that declare() then computes
        # from others (a law's D, OilColumn's k from K and L) would lose them
        # silently, so bind() refuses there a given value other than the default
        set_(self, "_given", {n for n, v in values.items() if not isinstance(v, ca.SX)})
        set_(self, "_declaring", True)
        decls = {}
        for cls in reversed(type(self).__mro__):
            for n, d in vars(cls).items():
                if isinstance(d, Parameter):
                    decls[n] = d
        for n, d in decls.items():
            self._add_param(n, d, values.pop(n, d.default))
        # the rest may be parameters that declare() makes (a law's own, such as
        # Volume(law="linear").K1): taken there, refused after it
        set_(self, "_pending", values)
        self.declare()
        set_(self, "_declaring", False)
        if values:
            raise ParameterError(
                f"{type(self).__name__}: unknown parameter(s) {', '.join(sorted(values))}; "
                f"it has: {', '.join(self._params) or 'none'}")

    # -- what subclasses write ------------------------------------------------
    def declare(self) -> None:
        """Declare connectors, variables and sub-components as attributes."""

    def equations(self) -> list:
        """Residual expressions (``eq(lhs, rhs)``) of this component alone."""
        return []

    def events(self) -> list:
        """(expression, label) or (expression, label, description) tuples whose
        sign changes mark non-smooth points (the description says which: an
        FMU's event indicators carry it)."""
        return []

    def initial_equations(self) -> list:
        """Residuals that hold at the start only (may use der()); together they
        determine the states declared ``fixed=False``, whose start values are
        then only guesses."""
        return []

    def free(self, *names: str) -> None:
        """Make the start of some of this component's states free: only a
        guess, solved from the initial equations (Modelica's ``fixed=false``).

        Parameters
        ----------
        *names : str
            The states, by their names in this component (``"v"``).

        Raises
        ------
        pdbfs.ModelError
            For a name that is not a state of this component.
        """
        for n in names:
            slot = self._vars.get(n)
            if slot is None or not slot.decl.is_state:
                raise ModelError(f"{self.label()}: {n!r} is not a state of it")
            slot.decl.fixed = False
        self._changed()

    def conditions(self) -> list:
        """(expression, text, names): physical consistency of the parameters.
        Each expression (of parameters only) must be >= 0, else a run is
        refused, naming this component, the parameters ``names`` and their
        values, and saying ``text``."""
        return []

    def time_events(self) -> list:
        """(time, label) or (time, label, description) tuples: the times
        (numbers or expressions of parameters) at which an input switches. Every integrator stops and
        restarts there, so that no step can jump over a switch."""
        return []

    # -- declaration plumbing -------------------------------------------------
    def _add_param(self, name, decl, value):
        if isinstance(value, Parameter):
            raise ParameterError(f"{type(self).__name__}.{name}: pass a value, not a Parameter")
        if not isinstance(value, ca.SX):
            value = self._number(name, decl, value)
        slot = ParamSlot(decl, name, value)
        self._params[name] = slot
        object.__setattr__(self, name, slot.sym)

    def bind(self, name: str, value: float | ca.SX) -> None:
        """Give a parameter of this component a new default, or make it
        computed from others.

        Called in ``declare()`` (a law that sets a stiffness from a
        material's constants) or on a built component.

        Parameters
        ----------
        name : str
            The parameter, by its name in this component.
        value : float or casadi.SX
            A number (its new default, SI units, checked against the
            declaration), or an expression of other parameters' symbols
            (the parameter is then computed and cannot be set in a run).

        Raises
        ------
        pdbfs.ParameterError
            For a number out of the declaration's bounds, or an expression in
            place of a value the caller gave the constructor.
        """
        slot = self._params[name]
        if isinstance(value, ca.SX) and name in self._given and self._declaring \
                and slot.value != slot.decl.default:
            mine = {x.element_hash() for x in ca.symvar(value)}
            others = [n for n, p in self._params.items()
                      if n != name and p.sym.element_hash() in mine] or ["the law's parameters"]
            raise ParameterError(
                f"{type(self).__name__}: {name} is computed from {', '.join(others)} here "
                f"and cannot be given; set those instead")
        if not isinstance(value, ca.SX):
            value = self._number(name, slot.decl, value)
        slot.value = value

    def _number(self, name, decl, value) -> float:
        """A parameter's number, checked: a number (not text, not a bool, whose
        float() would pass) within the declaration's bounds."""
        where = f"{type(self).__name__}.{name}"
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
            raise ParameterError(f"{where} = {plain(value)}: not a number {described(decl)}; "
                                 "give a number or an expression of parameters")
        return decl.check(value, where)

    def __setattr__(self, name, value):
        if name.startswith("_"):
            object.__setattr__(self, name, value)
            return
        if isinstance(value, Parameter):   # a parameter declared in declare()
            value.name = name
            self._add_param(name, value, self.__dict__.get("_pending", {}).pop(name, value.default))
            return
        if isinstance(value, RigInput):    # the rig's input, named by this component
            if self._inputs:
                raise ModelError(f"{self.label()}: declares a second input ({name}); a "
                                 "component holds one (the input is named by it)")
            slot = self._inputs[name] = InputSlot(value, name)
            value = slot.expr
        elif isinstance(value, Variable):
            slot = VarSlot(value, name)
            self._vars[name] = slot
            value = slot.sym
        elif isinstance(value, Connector):
            value._attach(self, name)
            self._connectors[name] = value
        elif isinstance(value, Component):
            if value._parent is not None:
                raise ConnectError(f"component {value.path()} is already part of a rig")
            object.__setattr__(value, "_name", name)
            object.__setattr__(value, "_parent", self)
            self._children[name] = value
        object.__setattr__(self, name, value)

    # -- names ----------------------------------------------------------------
    def path(self) -> str:
        """The dotted path of this component in its rig ("" for the rig itself)."""
        if self._parent is None:
            return ""
        up = self._parent.path()
        return f"{up}.{self._name}" if up else self._name

    def label(self) -> str:
        """The path and class, as messages name a component ("contact (ImpactContact)")."""
        return f"{self.path() or 'the rig'} ({type(self).__name__})"

    def walk(self) -> Iterator[Component]:
        """This component and every descendant, parents first."""
        yield self
        for child in self._children.values():
            yield from child.walk()

    # -- connections ----------------------------------------------------------
    def connect(self, *connectors: Connector) -> None:
        """Connect two or more connectors of this rig's components: their
        across variables equal (position, pressure, temperature, a signal's
        value) and their through variables summing to zero (force, flow,
        heat flow).

        Parameters
        ----------
        *connectors : Connector
            Two or more connectors of one kind (``self.hammer.flange_b``,
            ``self.contact.flange_a``), each of a component that is part of
            this rig; signals of one unit.

        Raises
        ------
        pdbfs.ConnectError
            For fewer than two connectors, something that is not one, one
            outside this rig or given twice, kinds that do not meet, or
            signals of different units.
        """
        if len(connectors) < 2:
            raise ConnectError(f"connect() in {self.label()} needs at least two connectors")
        for c in connectors:
            if not isinstance(c, Connector):
                raise ConnectError(
                    f"connect() in {self.label()}: {_describe(c)} is not a connector "
                    "(connect flanges, e.g. hammer.flange_b, not components or variables)")
            if not self._owns(c):
                owner = c.owner.label() if c.owner is not None and c.owner.path() else \
                    f"a {type(c.owner).__name__}"
                raise ConnectError(f"connect() in {self.label()}: {c.name} of {owner} is not part "
                                   "of this rig (assign the component to an attribute of the rig)")
        seen = set()
        for c in connectors:
            if id(c) in seen:
                raise ConnectError(f"connect(): {c.path()} is connected to itself")
            seen.add(id(c))
        kinds = {c.kind for c in connectors}
        if len(kinds) > 1:
            desc = ", ".join(f"{c.path()} ({type(c).__name__})" for c in connectors)
            raise ConnectError(f"connect(): incompatible connectors: {desc}")
        if kinds == {"signal"}:
            units = {signal_unit(c.unit) for c in connectors}
            if len(units) > 1:      # the one rule of export-ssp too: "" and "1" alike
                desc = ", ".join(f"{c.path()} in {signal_unit(c.unit)}" for c in connectors)
                raise ConnectError(f"connect(): signals of different units: {desc}; join signals "
                                   "of one unit (a Gain with unit= and input_unit= converts)")
        self._connections.append(tuple(connectors))
        self._changed()

    def _changed(self):
        """This component's declaration changed: its compiled DAE, and that of
        every rig it is part of, are made again when next asked for (a rig
        that kept its DAE would simulate what it was before)."""
        comp = self
        while comp is not None:
            object.__setattr__(comp, "_compiled", None)
            comp = comp._parent

    def _owns(self, c: Connector) -> bool:
        comp = c.owner
        while comp is not None:
            if comp is self:
                return True
            comp = comp._parent
        return False

    # -- compile ----------------------------------------------------------------
    def compile(self) -> DAE:
        """The simplified CasADi DAE of this rig, built once, then kept (a
        rig of pdbfs's own components whose declaration was compiled before,
        by any process, is read from pdbfs's cache folder)."""
        if self._compiled is None:
            from . import dae_cache
            key = dae_cache.declaration_key(self)
            dae = dae_cache.load(key) if key is not None else None
            if dae is None:
                # flattening and structural analysis (scipy.sparse): imported when needed
                from .flatten import flatten
                from .pressure_bound import pressure_bound
                from .structure import simplify
                dae = simplify(flatten(self), name=self.rig_name())
                dae.signals = dict(getattr(self, "summary_signals", {}) or {})
                dae.pressure_bound = pressure_bound(self)
                dae.description = _first_sentence(type(self).__doc__)
                if key is not None:
                    dae_cache.store(key, dae)
            object.__setattr__(self, "_compiled", dae)
        return self._compiled

    def rig_name(self) -> str:
        """The DAE's and the FMU's name: the class attribute ``name``, else the class name."""
        return getattr(self, "name", None) or type(self).__name__


def switch_times(component, breakpoints) -> list:
    """``breakpoints`` (numbers or parameter expressions, or a callable
    returning them) as a component's time_events()."""
    times = breakpoints() if callable(breakpoints) else breakpoints
    out = []
    for i, b in enumerate(times or ()):
        if not isinstance(b, ca.SX):
            try:
                b = float(b)
            except (TypeError, ValueError):
                raise ParameterError(f"{component.label()}: breakpoint {b!r} is not a time "
                                     "(a number in s or an expression of parameters)") from None
        out.append((ca.SX(b), f"switch {i + 1}"))
    return out


def _first_sentence(doc: str | None) -> str:
    """What a rig is, from its class docstring: the first sentence."""
    text = " ".join((doc or "").split("\n\n")[0].split())
    return text.split(". ")[0].rstrip(".") + "." if text else ""


def _describe(obj) -> str:
    """A thing passed to connect(), named as the rig knows it."""
    if isinstance(obj, Component):
        return f"component {obj.label()}" if obj.path() else \
            f"a {type(obj).__name__} that is not part of the rig"
    return f"{type(obj).__name__} {obj!r}"[:80]
