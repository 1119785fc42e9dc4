"""Jumps made by source blocks (a Step, a Pulse through a DeadZone, a held
Table) pushing a mass-spring-damper: every switch ends one integration and
starts the next, and the piece before a switch never sees the value after
it. The velocity against the closed form, on both back ends at their
defaults, on a grid of switch times (on output points and between them).
Before, the CasADi back end's last steps before a switch at an output point
saw the value after it: a Pulse through a DeadZone left 3.4e-6 of the
velocity's scale, a held Table 8.8e-6 (the compiled one: 1.6e-7)."""
import math

import numpy as np
import pytest

import pdbfs
from input_rigs import C, K, M, Pushed
from pdbfs.components import Damper, Fixed, Mass, SignalForce, Spring
from pdbfs.components import blocks as B

#: each back end at its defaults, of the velocity's largest value
BOUND = 5e-7
WN, ZETA = math.sqrt(K / M), C / (2 * math.sqrt(K * M))
WD = WN * math.sqrt(1 - ZETA ** 2)


def v_step(t, F, ts):
    """The velocity of m x'' + c x' + k x = F H(t - ts), at rest before."""
    tau = np.clip(t - ts, 0.0, None)
    return F / (M * WD) * np.exp(-ZETA * WN * tau) * np.sin(WD * tau)


class DeadZoned(pdbfs.Rig):
    """The mass-spring-damper pushed by ``source`` through a DeadZone of +-1."""

    def __init__(self, source, **kw):
        self._source = source
        super().__init__(**kw)

    def declare(self):
        self.frame, self.spring, self.damper = Fixed(), Spring(k=K), Damper(c=C)
        self.body, self.push = Mass(m=M), SignalForce()
        self.src, self.dz = self._source, B.DeadZone(uMax=1.0, uMin=-1.0, unit="N")
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.body.flange_a)
        self.connect(self.body.flange_b, self.push.flange)
        self.connect(self.src.y, self.dz.u)
        self.connect(self.dz.y, self.push.u)


def _cases():
    out = []
    for ts in (0.1, 0.2, 0.12345):           # on output points (every 1 ms) and between
        out.append((f"step@{ts}", lambda ts=ts: Pushed(B.Step(unit="N", height=10.0, start_time=ts)),
                    lambda t, ts=ts: v_step(t, 10.0, ts)))
        out.append((f"pulse-deadzone@{ts}", lambda ts=ts: DeadZoned(
            B.Pulse(unit="N", amplitude=5.0, width=0.037, period=0.1, start_time=ts, periods=3)),
            lambda t, ts=ts: sum(v_step(t, 4.0, ts + 0.1 * k) - v_step(t, 4.0, ts + 0.1 * k + 0.037)
                                 for k in range(3))))
        times = [0.0, ts - 0.05, ts, ts + 0.0777]
        out.append((f"table-hold@{ts}", lambda times=times: Pushed(
            B.Table(times, [0.0, 3.0, -2.0, 1.0], interpolation="hold", unit="N")),
            lambda t, tt=times: v_step(t, 3.0, tt[1]) + v_step(t, -5.0, tt[2]) + v_step(t, 3.0, tt[3])))
    return out


CASES = _cases()


@pytest.mark.parametrize("name,make,want", CASES, ids=[c[0] for c in CASES])
def test_source_jumps_on_both_back_ends(name, make, want):
    rig = make()
    got = {}
    for backend in ("c", "casadi"):
        res = rig.simulate(0.5, n_out=501, backend=backend)
        exact = want(res.t)
        scale = np.max(np.abs(exact))
        got[backend] = res["body.v"]
        assert np.max(np.abs(got[backend] - exact)) < BOUND * scale, backend
    assert np.max(np.abs(got["c"] - got["casadi"])) < BOUND * scale
