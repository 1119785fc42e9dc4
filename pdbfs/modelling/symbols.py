"""Declarations a component makes: parameters, variables, and der().

A component declares ``Parameter`` objects as class attributes and
``State``/``Variable`` objects in ``declare()``; the component turns each into
a CasADi SX symbol, so equations are plain CasADi expressions.
"""
from __future__ import annotations

import math

import casadi as ca
import numpy as np

from pdbfs.errors import ModelError

#: The independent variable, shared by every component.
time = ca.SX.sym("time")


class Parameter:
    """A parameter declaration: default value, SI unit, meaning and bounds.

    Declared as a class attribute of a component; the component's
    constructor takes its value by the attribute's name (``Mass(m=2.0)``),
    and a rig's run by its dotted path (``params={"hammer.m": 2.0}``).

    Parameters
    ----------
    default : float
        The value a component gets when it is not given one, in ``unit``.
    unit : str
        The SI unit ("kg", "N/m", "Pa"; "1" for a dimensionless one), shown
        in the docs, the results and the FMU.
    description : str
        What the parameter means, one line.
    min, max : float, optional
        Inclusive bounds; a value outside them is refused with a
        ParameterError naming the parameter.
    positive : bool
        Whether the value must be strictly greater than zero.
    tunable : bool
        False where a change during a run means nothing (a start value, a
        mass): the FMU marks such a parameter fixed.
    """

    def __init__(self, default: float, unit: str, description: str, *, min: float | None = None,
                 max: float | None = None, positive: bool = False, tunable: bool = True):
        self.default = default
        self.unit = unit
        self.description = description
        self.min = min
        self.max = max
        self.positive = positive
        self.tunable = tunable
        self.name = None

    def __set_name__(self, owner, name):
        self.name = name

    def check(self, value: float, where: str) -> float:
        """The value as a float, checked against this declaration.

        Parameters
        ----------
        value : float
            The value to check, in the declaration's unit.
        where : str
            The name the error message gives it (``"hammer.m"``).

        Returns
        -------
        float
            ``value`` as a float.

        Raises
        ------
        pdbfs.ParameterError
            If it is not a finite number, or is out of the declaration's bounds.
        """
        return check_value(value, where, self)


def quantity(value, unit: str, fmt: str = "g") -> str:
    """``value`` with its unit as a message shows it ("0.5 m"); a
    dimensionless one ("1" or "") bare ("0.5", never "0.5 1")."""
    text = format(value, fmt) if isinstance(value, (int, float, np.floating)) else str(value)
    return f"{text} {unit}" if unit and unit != "1" else text


def described(spec) -> str:
    """"(what it is, unit)" of a parameter's declaration, the unit left out where there is none."""
    return f"({spec.description}, {spec.unit})" if spec.unit and spec.unit != "1" else \
        f"({spec.description})"


def check_value(value, where: str, spec) -> float:
    """Check ``value`` against ``spec`` (anything with unit, description, min,
    max, positive) and return it as a float."""
    from pdbfs.errors import ParameterError, plain
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{where} = {plain(value)}: not a number {described(spec)}") from None
    if not math.isfinite(v):
        raise ParameterError(f"{where} = {v}: must be finite {described(spec)}")
    if spec.positive and v <= 0:
        raise ParameterError(f"{where} = {quantity(v, spec.unit)}: must be > 0 ({spec.description})")
    if spec.min is not None and v < spec.min:
        raise ParameterError(f"{where} = {quantity(v, spec.unit)}: must be >= {spec.min:g} "
                             f"({spec.description})")
    if spec.max is not None and v > spec.max:
        raise ParameterError(f"{where} = {quantity(v, spec.unit)}: must be <= {spec.max:g} "
                             f"({spec.description})")
    return v


def within_limits(values, spec):
    """check_value's rules on an array at once: True where a value would pass
    (finite, > 0 if ``spec.positive``, within ``spec.min`` and ``spec.max``)."""
    v = np.asarray(values, dtype=float)
    ok = np.isfinite(v)
    with np.errstate(invalid="ignore"):
        if spec.positive:
            ok &= v > 0
        if spec.min is not None:
            ok &= v >= spec.min
        if spec.max is not None:
            ok &= v <= spec.max
    return ok


class Variable:
    """An algebraic variable declaration, made in a component's ``declare()``
    (``self.f = Variable("N", "Contact force", output=True)``).

    Parameters
    ----------
    unit : str
        The variable's SI unit ("1" for a dimensionless one).
    description : str
        What the variable is, one line.
    output : bool
        Whether it is a result users look at: an output of the FMU, and of
        the rig's summaries and plots.
    start : float or casadi.SX, optional
        A guess for solving the start (a number or an expression of the
        component's parameters); None: the compiler's own.
    min, max : float, optional
        Bounds, SI, of the values the component's equations describe (a
        chamber's volume stays above 0): a run that takes the variable out
        of them stops there with a SolverError naming it and the time.
    beyond : str
        What leaving the bounds means, said in that error message.

    Raises
    ------
    pdbfs.ModelError
        For a bound that is not a finite number, or ``min`` not below ``max``.
    """

    is_state = False

    def __init__(self, unit: str, description: str, *, output: bool = False,
                 start: float | ca.SX | None = None, min: float | None = None,
                 max: float | None = None, beyond: str = ""):
        self.unit = unit
        self.description = description
        self.output = output
        self.start = start
        for what, b in (("min", min), ("max", max)):
            if b is not None and not (isinstance(b, (int, float)) and not isinstance(b, bool)
                                      and np.isfinite(b)):
                raise ModelError(f"Variable {description!r}: {what} = {b!r} must be a finite number")
        if min is not None and max is not None and not min < max:
            raise ModelError(f"Variable {description!r}: min = {min!r} must be below max = {max!r}")
        self.min = None if min is None else float(min)
        self.max = None if max is None else float(max)
        self.beyond = beyond


class State(Variable):
    """A variable that appears differentiated, declared in a component's
    ``declare()`` (``self.v = State("m/s", "Velocity", start=self.v0)``).

    Parameters
    ----------
    unit : str
        The state's SI unit.
    description : str
        What the state is, one line.
    start : float or casadi.SX
        Its value at t = 0: a number or an expression of the component's
        parameters.
    output : bool
        Whether it is a result users look at (an FMU output).
    fixed : bool
        False (Modelica's word) makes ``start`` only a guess: the state's
        start is then solved from the component's initial equations
        (``Component.initial_equations``).
    min, max : float, optional
        Bounds, SI, of the values the equations describe; a run that leaves
        them stops there with a SolverError naming the state and the time.
    beyond : str
        What leaving the bounds means, said in that error message.

    Raises
    ------
    pdbfs.ModelError
        For a bound that is not a finite number, or ``min`` not below ``max``.
    """

    is_state = True

    def __init__(self, unit: str, description: str, *, start: float | ca.SX = 0.0,
                 output: bool = True, fixed: bool = True, min: float | None = None,
                 max: float | None = None, beyond: str = ""):
        super().__init__(unit, description, output=output, start=start, min=min, max=max,
                         beyond=beyond)
        self.fixed = bool(fixed)


# der() symbols, keyed by the element hash of the variable they differentiate.
# The variable itself is kept in the value so its hash cannot be reused.
_DER: dict[int, tuple[ca.SX, ca.SX]] = {}


def _scalar_symbol(v, what: str):
    if not isinstance(v, ca.SX) or not v.is_scalar() or not v.is_symbolic():
        raise ModelError(f"{what} takes one declared variable, got {v!r}")
    return v


def der(v: ca.SX) -> ca.SX:
    """The time derivative of a declared variable, as a symbol of its own.

    Parameters
    ----------
    v : casadi.SX
        A state or variable of a component (one scalar symbol).

    Returns
    -------
    casadi.SX
        The symbol ``der(v)``, the same one on every call with ``v``.

    Raises
    ------
    pdbfs.ModelError
        If ``v`` is not one declared variable (an expression, a number).

    Examples
    --------
    In a component's ``equations()``, ``eq(der(self.s), self.v)``; on a
    bare symbol:

    >>> import casadi as ca
    >>> from pdbfs import der
    >>> der(ca.SX.sym("s"))
    SX(der(s))
    """
    _scalar_symbol(v, "der()")
    h = v.element_hash()
    if h not in _DER:
        _DER[h] = (v, ca.SX.sym(f"der({v.name()})"))
    return _DER[h][1]


def der_of(v: ca.SX):
    """The der() symbol of ``v`` if der(v) was ever asked for, else None."""
    hit = _DER.get(v.element_hash())
    return hit[1] if hit is not None else None


def eq(lhs: ca.SX | float, rhs: ca.SX | float) -> ca.SX:
    """An equation ``lhs = rhs`` in the residual form the compiler works with.

    Parameters
    ----------
    lhs, rhs : casadi.SX or float
        The two sides: expressions of the component's symbols, or numbers.

    Returns
    -------
    casadi.SX
        The residual ``lhs - rhs``, zero where the equation holds.
    """
    return lhs - rhs
