"""The dynamic blocks against their analytic responses: Integrator,
FirstOrder, SecondOrder (under- and overdamped) and Derivative on steps and
ramps; the PID's parts open loop on a ramp (P, PI, PD, PID, their start
values), its output limits with anti-windup by back-calculation (closed
form of the saturated integral), and a PI loop around a first-order plant.
Both back ends, at rtol 1e-10."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.components import blocks as B

BACKENDS = ["c", "casadi"]
TIGHT = dict(rtol=1e-10, atol=1e-12)


class Driven(pdbfs.Rig):
    """``block`` driven by ``source``."""

    def __init__(self, source, block, **kw):
        self._source, self._block = source, block
        super().__init__(**kw)

    def declare(self):
        self.src = self._source
        self.block = self._block
        self.connect(self.src.y, self.block.u)


def response(source, block, t_end, backend, n_out=1001):
    return Driven(source, block).simulate(t_end, n_out=n_out, backend=backend, **TIGHT)


def near(got, want, scale):
    return np.max(np.abs(got - want)) < 1e-7 * scale


@pytest.mark.parametrize("backend", BACKENDS)
def test_integrator(backend):
    res = response(B.Sine(amplitude=2.0, f=1.5), B.Integrator(k=3.0, y_start=-0.4), 2.0, backend)
    w = 2 * math.pi * 1.5
    assert near(res["block.y"], -0.4 + 3.0 * 2.0 / w * (1 - np.cos(w * res.t)), 1.0)


@pytest.mark.parametrize("backend", BACKENDS)
def test_first_order_step_response(backend):
    k, T, y0, h, ts = 2.0, 0.15, 0.7, 3.0, 0.2
    res = response(B.Step(height=h, start_time=ts), B.FirstOrder(k=k, T=T, y_start=y0), 1.5,
                   backend)
    t = res.t
    y_ts = y0 * math.exp(-ts / T)
    want = np.where(t < ts, y0 * np.exp(-t / T),
                    y_ts * np.exp(-(t - ts) / T) + k * h * (1 - np.exp(-(t - ts) / T)))
    assert near(res["block.y"], want, k * h)


def second_order_step(t, k, w, D):
    """Unit-step response of k w^2/(s^2 + 2 D w s + w^2) and its rate."""
    if D < 1:
        wd = w * math.sqrt(1 - D * D)
        decay = np.exp(-D * w * t)
        y = k * (1 - decay * (np.cos(wd * t) + D / math.sqrt(1 - D * D) * np.sin(wd * t)))
        return y, k * w / math.sqrt(1 - D * D) * decay * np.sin(wd * t)
    r1, r2 = -w * (D - math.sqrt(D * D - 1)), -w * (D + math.sqrt(D * D - 1))
    e1, e2 = np.exp(r1 * t), np.exp(r2 * t)
    return k * (1 + (r2 * e1 - r1 * e2) / (r1 - r2)), k * r1 * r2 * (e1 - e2) / (r1 - r2)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("D", [0.2, 2.5])
def test_second_order_step_response(backend, D):
    k, w = 1.5, 20.0
    res = response(B.Step(), B.SecondOrder(k=k, w=w, D=D), 1.0, backend)
    y, rate = second_order_step(res.t, k, w, D)
    assert near(res["block.y"], y, k)
    assert near(res["block.xd"], rate, k * w)


@pytest.mark.parametrize("backend", BACKENDS)
def test_derivative_of_a_ramp(backend):
    """u = r t, x(0) = x0: y = k (r T - (x0 + r T) exp(-t/T)) / T, tending
    to k r, the derivative."""
    k, T, r, x0 = 0.5, 0.02, 4.0, 0.3
    res = response(B.Ramp(height=r * 10.0, duration=10.0), B.Derivative(k=k, T=T, x_start=x0),
                   0.6, backend)
    want = k * (r * T - (x0 + r * T) * np.exp(-res.t / T)) / T
    assert near(res["block.y"], want, k * r + k * x0 / T)
    assert res["block.y"][-1] == pytest.approx(k * r, rel=1e-9)


def pid_on_ramp(t, r, kind, k=1.0, Ti=1.0, Td=0.1, Nd=10.0, xi_start=0.0, xd_start=0.0):
    """Output of the unlimited PID for the input u = r t."""
    y = k * r * t
    if "I" in kind:
        y = y + xi_start + k * r * t ** 2 / (2 * Ti)
    if "D" in kind:
        Tf = Td / Nd
        y = y + k * (r * Td - Nd * (xd_start + r * Tf) * np.exp(-t / Tf))
    return y


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("kind", ["P", "PI", "PD", "PID"])
def test_pid_parts_open_loop_on_a_ramp(backend, kind):
    gains = dict(k=2.0)
    if "I" in kind:
        gains.update(Ti=0.4, xi_start=0.25)
    if "D" in kind:
        gains.update(Td=0.05, Nd=8.0, xd_start=-0.1)
    pid = B.PID(kind=kind, **gains)
    assert {"Ti", "xi_start"} <= set(pid._params) if "I" in kind else "Ti" not in pid._params
    assert {"Td", "Nd"} <= set(pid._params) if "D" in kind else "Td" not in pid._params
    r = 3.0
    res = response(B.Ramp(height=r * 10.0, duration=10.0), pid, 1.0, backend)
    want = pid_on_ramp(res.t, r, kind, **gains)
    assert near(res["block.y"], want, np.max(np.abs(want)))


@pytest.mark.parametrize("backend", BACKENDS)
def test_pid_limits_and_back_calculation_on_a_ramp(backend):
    """A limited PI on u = r t: y = k r t + k r t^2/(2 Ti) until it reaches
    yMax at ts; then y = yMax and the integral obeys
    der(xi) = k u/Ti + (yMax - k u - xi)/Tt (Tt = Ni Ti), a linear ODE whose
    solution is xi_p(t) + (xi(ts) - xi_p(ts)) exp(-(t - ts)/Tt)."""
    k, Ti, Ni, r, ymax = 2.0, 0.5, 0.3, 1.0, 1.5
    pid = B.PID(kind="PI", limited=True, k=k, Ti=Ti, Ni=Ni, yMax=ymax, yMin=-1.0)
    res = response(B.Ramp(height=r * 10.0, duration=10.0), pid, 2.0, backend, n_out=2001)
    t = res.t
    ts = Ti * (-1 + math.sqrt(1 + 2 * ymax / (k * r * Ti)))
    Tt = Ni * Ti
    a, b = k * r * (1 / Ti - 1 / Tt), ymax / Tt
    c1 = a * Tt
    c0 = (b - c1) * Tt
    xi_ts = k * r * ts ** 2 / (2 * Ti)
    xi = np.where(t < ts, k * r * t ** 2 / (2 * Ti),
                  c1 * t + c0 + (xi_ts - (c1 * ts + c0)) * np.exp(-(t - ts) / Tt))
    assert 0.3 < ts < 1.0
    assert near(res["block.xi"], xi, ymax)
    assert near(res["block.y"], np.minimum(k * r * t + k * r * t ** 2 / (2 * Ti), ymax), ymax)
    # wound up without back-calculation the integral would be k r t^2/(2 Ti): 8 at 2 s
    assert res["block.xi"][-1] < 0.3 * k * r * 2.0 ** 2 / (2 * Ti)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_pi_loop_around_a_first_order_plant(backend):
    """Plant K/(tau s + 1), PI with Ti = tau: the loop is first order with
    the time constant tau/(k K); the controller's output is
    k r exp(-a t) + r (1 - exp(-a t))/K, a = k K/tau."""
    K, tau, k, r = 2.0, 0.5, 3.0, 1.2

    class Loop(pdbfs.Rig):
        def declare(self):
            self.setpoint = B.Step(height=r)
            self.error = B.Add(k2=-1.0)
            self.control = B.PID(kind="PI", k=k, Ti=tau)
            self.plant = B.FirstOrder(k=K, T=tau)
            self.connect(self.setpoint.y, self.error.u1)
            self.connect(self.plant.y, self.error.u2)
            self.connect(self.error.y, self.control.u)
            self.connect(self.control.y, self.plant.u)

    res = Loop().simulate(1.0, n_out=1001, backend=backend, **TIGHT)
    a = k * K / tau
    decay = np.exp(-a * res.t)
    assert near(res["plant.y"], r * (1 - decay), r)
    assert near(res["control.y"], k * r * decay + r * (1 - decay) / K, k * r)
