"""Rigs with inputs for tests/test_inputs*.py: a mass-spring-damper pushed
through SignalForce by a signal (an Input or a source block), and the
valve-driven pulse rig whose valve follows a command (an Input or a Table)."""
import math

import numpy as np

import pdbfs
from pdbfs.components import Damper, Fixed, Mass, PositionSensor, SignalForce, Spring
from pdbfs.components import blocks as B
from pdbfs.components import hydraulic as H

M, C, K = 1.0, 4.0, 400.0          # kg, N.s/m, N/m: lightly damped (zeta 0.1)
TIGHT = dict(rtol=1e-10, atol=1e-12)
BACKENDS = ["c", "casadi"]


class Pushed(pdbfs.Rig):
    """A mass on a spring and damper to the frame, pushed by the signal of
    ``source`` (default: the rig's input ``u``, N) through SignalForce."""

    def __init__(self, source=None, **kw):
        self._source = source
        super().__init__(**kw)

    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=K)
        self.damper = Damper(c=C)
        self.body = Mass(m=M)
        self.push = SignalForce()
        self.pos = PositionSensor()
        self.u = self._source if self._source is not None else B.Input("N", description="Force")
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.body.flange_a,
                     self.pos.flange)
        self.connect(self.body.flange_b, self.push.flange)
        self.connect(self.u.y, self.push.u)


def msd_step(t, F, ts):
    """x(t) of m x'' + c x' + k x = F*H(t - ts), at rest at the start."""
    wn, z = math.sqrt(K / M), C / (2 * math.sqrt(K * M))
    wd, tau = wn * math.sqrt(1 - z * z), np.clip(t - ts, 0.0, None)
    return F / K * (1 - np.exp(-z * wn * tau) * (np.cos(wd * tau)
                                                 + z / math.sqrt(1 - z * z) * np.sin(wd * tau)))


def msd_sine(t, A, f, phase=0.0, ts=0.0):
    """x(t) of m x'' + c x' + k x = A sin(2 pi f (t - ts) + phase) from ts on,
    at rest until then: the forced response plus the free one that starts
    it from rest."""
    w, tau = 2 * math.pi * f, np.clip(t - ts, 0.0, None)
    H = 1.0 / (K - M * w * w + 1j * C * w)
    xp = lambda s: A * np.imag(H * np.exp(1j * (w * s + phase)))          # noqa: E731
    dxp0 = A * np.imag(1j * w * H * np.exp(1j * phase))
    sigma = C / (2 * M)
    wd = math.sqrt(K / M - sigma ** 2)
    c1 = -xp(0.0)
    c2 = (sigma * c1 - dxp0) / wd
    x = xp(tau) + np.exp(-sigma * tau) * (c1 * np.cos(wd * tau) + c2 * np.sin(wd * tau))
    return np.where(t >= ts, x, 0.0)


#: the valve's command: open over 4 ms, held 0.5 ms, closed over 2 ms (as PulseValve's times)
COMMAND = (np.array([0.0, 4e-3, 4.5e-3, 6.5e-3, 0.05]), np.array([0.0, 1.0, 1.0, 0.0, 0.0]))


class CommandedPulse(pdbfs.Rig):
    """The valve-driven pulse rig (an ideal supply) whose valve opening follows
    ``command`` (default: the rig's input ``command``, 0..1)."""

    name = "commanded_pulse"
    summary_signals = {"pressure": "chamber.p"}

    def __init__(self, command=None, **kw):
        self._command = command
        super().__init__(**kw)

    def declare(self):
        self.supply = H.PressureSource(p=175e6)
        self.valve = H.CommandedValve(Cd=0.7, A=8e-5, dp_t=1e5)
        self.chamber = H.Volume(V=1e-3, K=1.5e9)
        self.drain = H.Orifice(Cd=0.7, A=4e-5, dp_t=1e5)
        self.tank = H.Tank()
        self.command = self._command if self._command is not None else \
            B.Input("1", description="Valve command, 0 closed to 1 open")
        self.connect(self.supply.port, self.valve.port_a)
        self.connect(self.valve.port_b, self.chamber.port, self.drain.port_a)
        self.connect(self.drain.port_b, self.tank.port)
        self.connect(self.command.y, self.valve.opening)


def msd_ramp(t, rate, tk):
    """x(t) of m x'' + c x' + k x = rate*(t - tk) from tk on, at rest until then."""
    sigma = C / (2 * M)
    wd = math.sqrt(K / M - sigma ** 2)
    tau = np.clip(t - tk, 0.0, None)
    g = C / K
    return rate / K * (tau - g + np.exp(-sigma * tau) * (g * np.cos(wd * tau)
                                                         + (g * sigma - 1.0) / wd * np.sin(wd * tau)))


class BaseExcited(pdbfs.Rig):
    """A mass on a spring and damper whose other end moves as the signal of
    ``source`` prescribes (SignalPosition): the damper needs the signal's
    rate, its first derivative."""

    def __init__(self, source=None, **kw):
        self._source = source
        super().__init__(**kw)

    def declare(self):
        from pdbfs.components import SignalPosition
        self.base = self._source if self._source is not None else B.Input("m")
        self.drive = SignalPosition()
        self.spring = Spring(k=K)
        self.damper = Damper(c=C)
        self.body = Mass(m=M)
        self.connect(self.base.y, self.drive.u)
        self.connect(self.drive.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.body.flange_a)


class ShakenMass(pdbfs.Rig):
    """A mass whose position an input (or the signal of ``source``)
    prescribes: its acceleration would be the signal's second derivative."""

    def __init__(self, source=None, **kw):
        self._source = source
        super().__init__(**kw)

    def declare(self):
        from pdbfs.components import SignalPosition
        self.base = self._source if self._source is not None else B.Input("m")
        self.drive = SignalPosition()
        self.body = Mass(m=2.0)
        self.spring = Spring(k=1e3)
        self.frame = Fixed()
        self.connect(self.base.y, self.drive.u)
        self.connect(self.drive.flange, self.body.flange_a)
        self.connect(self.body.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.frame.flange)


class ScaledCommandPulse(CommandedPulse):
    """The pulse rig whose valve follows a fixed command shape (a Table of
    COMMAND) times the rig's input ``scale`` (1 by default): an input that is
    a parameter of the command's trace."""

    def declare(self):
        self._command = B.Table(*COMMAND)
        super().declare()
        self.scale = B.Input("1", start=1.0, description="Scale of the valve's command")
        self.times = B.Product()
        self.connect(self.command.y, self.times.u1)
        self.connect(self.scale.y, self.times.u2)

    def connect(self, *connectors):
        # the valve follows the product, not the shape itself
        if connectors == (self.command.y, self.valve.opening):
            return
        super().connect(*connectors)
        if getattr(self, "times", None) is not None and connectors[0] is self.scale.y:
            super().connect(self.times.y, self.valve.opening)
