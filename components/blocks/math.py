"""Static blocks: the output is a function of the inputs now (after
Modelica.Blocks.Math and Nonlinear): gains, sums, products, limits. The
kinks of Limiter and DeadZone are event indicators."""
from __future__ import annotations

import casadi as ca

from pdbfs.modelling import Parameter, eq

from .interfaces import MISO, SISO


class Gain(SISO):
    """``y = k*u``; ``input_unit`` (the unit of ``u``, the output's by
    default) makes it a conversion: ``Gain(unit="N", input_unit="Pa",
    k=area)``.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    input_unit : str, optional
        The unit of its input ``u``, which its gain converts (default: ``unit``).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text.
    """

    converts = True

    k = Parameter(1.0, "1", "Gain (unit of y per unit of u)")

    def equations(self):
        return [eq(self.y.value, self.k * self.u.value)]


class Add(MISO):
    """The weighted sum ``y = k1*u1 + k2*u2 (+ ... + kn*un)``: ``n`` inputs
    (2 by default), each with its sign or weight ``ki`` (+1 by default);
    ``Add(k2=-1)`` gives the difference ``u1 - u2`` (a control error).

    Parameters
    ----------
    n : int
        The number of inputs ``u1 .. un`` (>= 1).
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or n that is not a whole number >= 1.
    """

    def declare(self):
        super().declare()
        for i in range(1, self._n + 1):
            setattr(self, f"k{i}", Parameter(1.0, "1", f"Weight (sign) of input u{i}"))

    def equations(self):
        weights = [getattr(self, f"k{i}") for i in range(1, self._n + 1)]
        return [eq(self.y.value, sum(k * u for k, u in zip(weights, self.input_values())))]


class Product(MISO):
    """The product of the ``n`` inputs (2 by default): ``y = u1*u2 (*...*un)``.

    Parameters
    ----------
    n : int
        The number of inputs ``u1 .. un`` (>= 1).
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or n that is not a whole number >= 1.
    """

    def equations(self):
        first, *rest = self.input_values()
        for u in rest:
            first = first * u
        return [eq(self.y.value, first)]


class PartialBounds(SISO):
    """A SISO block with an upper bound ``uMax`` and a lower bound ``uMin``
    of its input (``uMin <= uMax``); where ``u`` crosses either is an event.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    input_unit : None
        Not taken: its input is in the unit of its output (only a block with a
        gain converts; given, it is refused).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or an input_unit.
    """

    def declare(self):
        super().declare()
        self.uMax = self.signal_parameter(1.0, "Upper bound of the input")
        self.uMin = self.signal_parameter(-1.0, "Lower bound of the input")

    def conditions(self):
        return [(self.uMax - self.uMin, "the upper bound is below the lower bound",
                 ["uMin", "uMax"])]

    def events(self):
        return [(self.u.value - self.uMax, "upper", "the input crosses the upper bound uMax"),
                (self.u.value - self.uMin, "lower", "the input crosses the lower bound uMin")]


class Limiter(PartialBounds):
    """The input clamped to ``[uMin, uMax]``: ``y = min(max(u, uMin), uMax)``.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    input_unit : None
        Not taken: its input is in the unit of its output (only a block with a
        gain converts; given, it is refused).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or an input_unit.
    """

    def equations(self):
        return [eq(self.y.value, ca.fmin(ca.fmax(self.u.value, self.uMin), self.uMax))]


class DeadZone(PartialBounds):
    """No output while the input is inside ``[uMin, uMax]``, the excess
    outside it: ``y = u - uMax`` above, ``u - uMin`` below, 0 between.

    Parameters
    ----------
    unit : str
        The unit of its signals (SI text such as "N", "Pa", "m/s"; "1" for a
        plain number).
    input_unit : None
        Not taken: its input is in the unit of its output (only a block with a
        gain converts; given, it is refused).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), those that carry a signal's value in ``unit``.

    Raises
    ------
    pdbfs.ParameterError
        For a unit that is not a unit's text, or an input_unit.
    """

    def equations(self):
        u = self.u.value
        return [eq(self.y.value, ca.fmax(u - self.uMax, 0.0) + ca.fmin(u - self.uMin, 0.0))]
