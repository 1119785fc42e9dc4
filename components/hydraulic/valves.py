"""Valves: turbulent orifices whose opening follows the pressure
difference (relief and check valves), time (a fast switching valve) or a
signal (a commanded valve)."""
import casadi as ca

from pdbfs.modelling import Parameter, SignalInput, time

from .laws import smooth_step
from .resistances import PartialOrifice


class PartialPressureValve(PartialOrifice):
    """Opens as ``dp = port_a.p - port_b.p`` rises above the cracking
    pressure ``p_crack``, fully open at ``p_crack + dp_open``; the opening
    follows laws.smooth_step in between (continuous slope), so the flow is
    smooth in dp; closed (zero flow) below ``p_crack``, hence never
    backwards for ``p_crack >= 0``.

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    p_crack = Parameter(1e5, "Pa", "Cracking pressure difference", min=0.0)
    dp_open = Parameter(1e5, "Pa", "Pressure rise from cracking to fully open", positive=True)

    def opening(self):
        return smooth_step((self.dp - self.p_crack) / self.dp_open)

    def events(self):
        return [(self.dp - self.p_crack, "cracking", "the valve cracks open or reseats (dp = p_crack)")]


class CheckValve(PartialPressureValve):
    """A check (non-return) valve: flow only from port_a to port_b, once the
    pressure difference exceeds a small cracking pressure (PartialPressureValve's
    law: ``x = smooth_step((dp - p_crack)/dp_open)``).

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """


class ReliefValve(PartialPressureValve):
    """A pressure relief valve: port_a the protected line, port_b the tank;
    opens above its setting ``p_crack`` (PartialPressureValve's law:
    ``x = smooth_step((dp - p_crack)/dp_open)``).

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    p_crack = Parameter(20e6, "Pa", "Cracking (set) pressure difference", min=0.0)
    dp_open = Parameter(2e6, "Pa", "Pressure rise from cracking to fully open (the "
                        "override)", positive=True)


class TimedValve(PartialOrifice):
    """A valve driven by time: closed until ``t_open``, then opening over
    ``T_open`` (laws.smooth_step) and staying open: a fast switching valve,
    the orifice's opening ``x = smooth_step((t - t_open)/T_open)``.

    Connectors: ``port_a`` and ``port_b``; the flow ``q`` goes from a to b.

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    t_open = Parameter(1e-3, "s", "Time the valve starts to open", min=0.0)
    T_open = Parameter(2e-3, "s", "Time the valve takes to open fully", positive=True)

    def opening(self):
        return smooth_step((time - self.t_open) / self.T_open)

    def time_events(self):
        return [(self.t_open, "opening", "the valve starts opening (time = t_open)"),
                (self.t_open + self.T_open, "open", "the valve is fully open (time = t_open + T_open)")]


class PulseValve(TimedValve):
    """A TimedValve that closes again: starts closing at ``t_close`` and is
    shut ``T_close`` later (a pulse of flow), the opening
    ``x = smooth_step((t - t_open)/T_open)*(1 - smooth_step((t - t_close)/T_close))``.

    Connectors: ``port_a`` and ``port_b``; the flow ``q`` goes from a to b.

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    t_close = Parameter(4e-3, "s", "Time the valve starts to close", min=0.0)
    T_close = Parameter(2e-3, "s", "Time the valve takes to close", positive=True)

    def opening(self):
        return super().opening() * (1.0 - smooth_step((time - self.t_close) / self.T_close))

    def conditions(self):
        return super().conditions() + [
            (self.t_close - self.t_open, "the valve would start to close before it opens",
             ["t_open", "t_close"])]

    def time_events(self):
        return super().time_events() + [
            (self.t_close, "closing", "the valve starts closing (time = t_close)"),
            (self.t_close + self.T_close, "closed", "the valve is closed (time = t_close + T_close)")]


class CommandedValve(PartialOrifice):
    """A valve opened by the signal input ``opening`` (1: 0 closed, 1
    fully open, the flow area then ``A``): an orifice of area
    ``opening*A``, its opening ``x = min(max(opening, 0), 1)``. A command outside 0..1 is clamped there (a valve does not
    open beyond its stops), each stop an event.

    Connectors: ``port_a`` and ``port_b`` (the flow ``q`` goes from a to
    b), and the signal input ``opening``.

    Parameters
    ----------
    heat_port : bool
        Give it a heat port that takes the power of its flow, ``dp*q`` (the
        throttled oil warms).
    **params : float or casadi.SX
        Values of its declared parameters (the component catalogue lists
        them), SI units.
    """

    def declare(self):
        super().declare()
        self.opening = SignalInput("1", "Commanded opening, 0 closed to 1 fully open", min=0.0, max=1.0,
                                   nominal=1.0)

    def open_fraction(self):
        return ca.fmin(ca.fmax(self.opening.value, 0.0), 1.0)

    def events(self):
        x = self.opening.value
        return [(x, "closed", "the command reaches or leaves the closed stop (opening = 0)"),
                (x - 1.0, "open", "the command reaches or leaves the open stop (opening = 1)")]
