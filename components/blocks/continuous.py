"""Linear dynamic blocks (after Modelica.Blocks.Continuous): each a SISO
block with states of its own, started at the values of its ``*_start``
parameters. The PID controller is in pid.py."""
from __future__ import annotations

from pdbfs.modelling import Parameter, State, der, eq

from .interfaces import SISO


class Integrator(SISO):
    """``y = y_start + k * integral of u``: ``der(y) = k*u``.

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

    k = Parameter(1.0, "1/s", "Integrator gain (unit of y per unit of u and second)")
    converts = True          # input_unit: u in another unit, k converts

    def declare(self):
        super().declare()
        self.y_start = self.signal_parameter(0.0, "Output at the start", tunable=False)
        self.x = State(self._unit, "Integral (the output)", start=self.y_start)

    def equations(self):
        return [eq(der(self.x), self.k * self.u.value), eq(self.y.value, self.x)]


class FirstOrder(SISO):
    """A first-order lag ``k/(T*s + 1)``: ``T*der(y) = k*u - y``.

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

    k = Parameter(1.0, "1", "Steady-state gain (unit of y per unit of u)")
    converts = True          # input_unit: u in another unit, k converts
    T = Parameter(1.0, "s", "Time constant", positive=True)

    def declare(self):
        super().declare()
        self.y_start = self.signal_parameter(0.0, "Output at the start", tunable=False)
        self.x = State(self._unit, "Output of the lag", start=self.y_start)

    def equations(self):
        return [eq(self.T * der(self.x), self.k * self.u.value - self.x),
                eq(self.y.value, self.x)]


class SecondOrder(SISO):
    """A second-order lag ``k*w^2/(s^2 + 2*D*w*s + w^2)``: ``der(y) = yd``,
    ``der(yd) = w^2*(k*u - y) - 2*D*w*yd`` (undamped angular frequency
    ``w``, damping ratio ``D``).

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

    k = Parameter(1.0, "1", "Steady-state gain (unit of y per unit of u)")
    converts = True          # input_unit: u in another unit, k converts
    w = Parameter(1.0, "rad/s", "Undamped angular frequency", positive=True)
    D = Parameter(1.0, "1", "Damping ratio", min=0.0)

    def declare(self):
        super().declare()
        self.y_start = self.signal_parameter(0.0, "Output at the start", tunable=False)
        rate = per_second(self._unit)
        self.yd_start = Parameter(0.0, rate, "Rate of the output at the start", tunable=False)
        self.x = State(self._unit, "Output of the lag", start=self.y_start)
        self.xd = State(rate, "Rate of the output", start=self.yd_start)

    def equations(self):
        w = self.w
        return [eq(der(self.x), self.xd),
                eq(der(self.xd), w * w * (self.k * self.u.value - self.x)
                   - 2.0 * self.D * w * self.xd),
                eq(self.y.value, self.x)]


class Derivative(SISO):
    """A filtered derivative ``k*s/(T*s + 1)``: ``y = k*(u - x)/T`` with
    ``T*der(x) = u - x``; ``x`` starts at ``x_start``, so the output starts
    at ``k*(u(0) - x_start)/T`` (give ``x_start = u(0)`` for no kick). For
    ``T`` well below the input's time scales the output is ``k*der(u)``.

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

    k = Parameter(1.0, "s", "Gain (unit of y per unit of u's rate)")
    T = Parameter(0.01, "s", "Time constant of the filter", positive=True)

    def declare(self):
        super().declare()
        self.x_start = self.signal_parameter(0.0, "Start value of the filter's state (in the "
                                             "unit of u)", tunable=False)
        self.x = State(self._unit, "Filtered input", start=self.x_start)

    def equations(self):
        return [eq(self.T * der(self.x), self.u.value - self.x),
                eq(self.y.value, self.k * (self.u.value - self.x) / self.T)]


def per_second(unit: str) -> str:
    """The unit of a rate of a signal in ``unit``: "1/s", "N/s", "(m/s)/s"."""
    if unit == "1":
        return "1/s"
    return f"{unit}/s" if unit.isalnum() else f"({unit})/s"
