"""PID: a proportional-integral-derivative controller on the control error
``u``, with a filtered derivative, output limits and anti-windup."""
from __future__ import annotations

import casadi as ca

from pdbfs.errors import ParameterError
from pdbfs.modelling import Parameter, State, Variable, der, eq

from .interfaces import SISO

#: the controller types PID offers (``kind=``)
KINDS = ("P", "PI", "PD", "PID")


class PID(SISO):
    """A PID controller acting on its input ``u``, the control error (form
    it with ``Add(k2=-1)``: setpoint minus measurement). In parallel form,

        v = k*(u + I + D)      I = (1/Ti) * integral of u
                               D = Td*s/(Td/Nd*s + 1) applied to u

    so ``k*Td`` is the derivative gain and ``Nd`` bounds its high-frequency
    gain (the filter's time constant is ``Td/Nd``). ``kind`` ("P", "PI",
    "PD" or "PID", the default) says which parts there are; only those
    parts' parameters exist (Ti for I, Td and Nd for D).

    The states: ``xi``, the integral part in the unit of the output (``k*I``,
    starting at ``xi_start``), and ``xd``, the derivative filter's state in
    the unit of ``u`` (starting at ``xd_start``; the derivative part at the
    start is ``k*Nd*(u(0) - xd_start)``: give ``xd_start = u(0)`` for no
    kick).

    ``limited=True`` clamps the output to ``[yMin, yMax]`` (``y = min(max(v,
    yMin), yMax)``, each limit an event) and, with an integral part, stops
    the integral winding up by back-calculation: while the output is held
    at a limit, the integral is driven towards it,

        der(xi) = k*u/Ti + (y - v)/(Ni*Ti)

    with the tracking time ``Ni*Ti``; inside the limits ``y = v`` and the
    integral is the plain one. The unlimited controller is ``y = v``. In
    the states, ``v = k*u + xi + k*Nd*(u - xd)``, ``der(xi) = k*u/Ti`` and
    ``Td*der(xd) = Nd*(u - xd)``.

    Connectors: the signal input ``u`` (the control error) and output ``y``.

    Parameters
    ----------
    kind : {"PID", "P", "PI", "PD"}
        The parts there are (only their parameters exist).
    limited : bool
        Clamp the output to ``[yMin, yMax]``, with anti-windup of the
        integral part.
    unit : str
        The unit of its output (SI text; "1" for a plain number).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), and ``input_unit``: the unit of the control error ``u``
        (default: ``unit``), which the gain converts.

    Raises
    ------
    pdbfs.ParameterError
        For an unknown kind, a ``limited`` that is not True or False, or a
        unit that is not a unit's text.
    """

    k = Parameter(1.0, "1", "Gain (unit of y per unit of u)")
    converts = True          # input_unit: the control error's (a pressure's for a valve command)

    def __init__(self, kind: str = "PID", limited: bool = False, unit: str = "1", **params):
        if kind not in KINDS:
            raise ParameterError(f"PID: kind = {kind!r}; choose one of " + ", ".join(KINDS))
        if not isinstance(limited, bool):
            raise ParameterError(f"PID: limited = {limited!r} must be True or False")
        self._kind, self._limited = kind, limited
        super().__init__(unit=unit, **params)

    def declare(self):
        super().declare()
        if "I" in self._kind:
            self.Ti = Parameter(1.0, "s", "Integral time", positive=True)
            self.xi_start = self.signal_parameter(0.0, "Integral part of the output at the "
                                                  "start", tunable=False)
            self.xi = State(self._unit, "Integral part of the output", start=self.xi_start)
        if "D" in self._kind:
            self.Td = Parameter(0.1, "s", "Derivative time", positive=True)
            self.Nd = Parameter(10.0, "1", "Derivative filter ratio: the filter's time "
                                "constant is Td/Nd", positive=True)
            u_unit = self._input_unit or self._unit
            self.xd_start = Parameter(0.0, u_unit, "Start value of the derivative filter's "
                                      "state (in the unit of u)", tunable=False)
            self.xd = State(u_unit, "Control error through the derivative filter",
                            start=self.xd_start)
        if self._limited:
            self.yMax = self.signal_parameter(1.0, "Upper limit of the output")
            self.yMin = self.signal_parameter(-1.0, "Lower limit of the output")
            if "I" in self._kind:
                self.Ni = Parameter(1.0, "1", "Anti-windup tracking time as a fraction of Ti",
                                    positive=True)
            self.v = Variable(self._unit, "Output before the limits")

    def unlimited(self):
        """The output before the limits, ``k*u + xi + k*Nd*(u - xd)``."""
        u = self.u.value
        v = self.k * u
        if "I" in self._kind:
            v = v + self.xi
        if "D" in self._kind:
            v = v + self.k * self.Nd * (u - self.xd)
        return v

    def equations(self):
        u, y = self.u.value, self.y.value
        eqs = []
        if self._limited:
            eqs += [eq(self.v, self.unlimited()),
                    eq(y, ca.fmin(ca.fmax(self.v, self.yMin), self.yMax))]
        else:
            eqs.append(eq(y, self.unlimited()))
        if "I" in self._kind:
            rate = self.k * u / self.Ti
            if self._limited:
                rate = rate + (y - self.v) / (self.Ni * self.Ti)
            eqs.append(eq(der(self.xi), rate))
        if "D" in self._kind:
            eqs.append(eq(self.Td * der(self.xd), self.Nd * (u - self.xd)))
        return eqs

    def conditions(self):
        return [(self.yMax - self.yMin, "the upper output limit is below the lower one",
                 ["yMin", "yMax"])] if self._limited else []

    def events(self):
        if not self._limited:
            return []
        return [(self.v - self.yMax, "upper", "the output reaches or leaves its upper limit yMax"),
                (self.v - self.yMin, "lower", "the output reaches or leaves its lower limit yMin")]
