"""The pulse in the compiled summary driver (native/c/library/pdbfs_summary.c and
pdbfs_pulse.c):
crossings paired by direction with no cap, pulses cut off by t_end reported
without a duration (``complete`` 0, a message), crossings that do not
alternate a failed point; solver statistics per point."""
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.components import Fixed, Mass, Spring
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled as batch
from pdbfs.simulation.run.compiled import SUMMARY_KEYS

OK, CUT, BAD = 0, 1, 2
W = 2 * math.pi * 100.0          # the oscillator's angular frequency (100 Hz)
V0 = 1.0


class Oscillator(pdbfs.Rig):
    """A mass on a spring, its position playing the pressure's role:
    s = V0/W sin(W t), above 1 % of its peak for (pi - 2 asin(0.01))/W of
    every period, two crossings a period."""

    name = "oscillator"
    summary_signals = {"pressure": "body.s"}

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=1.0, v0=V0)
        self.spring = Spring(k=W ** 2)
        self.connect(self.frame.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.body.flange_a)


@pytest.fixture(scope="module")
def paper():
    rig = paper_rig()
    return rig, Simulator.of(rig)


@pytest.fixture(scope="module")
def oscillator():
    sim = Simulator.of(Oscillator())
    return sim, sim.compiled()


def test_pairing_by_direction(oscillator):
    _, lib = oscillator
    pairs = lib.pulse_pairs
    assert pairs([1, 2, 3, 5], [1, -1, 1, -1], 0, 0, 0, 6) == (OK, 3.0, "")
    assert pairs([], [], 0, 0, 0, 6)[:2] == (OK, 0.0)
    # more than 64 crossings: every pulse counts
    t = np.arange(300) * 1.0
    ans, dur, _ = pairs(t, np.where(np.arange(300) % 2 == 0, 1, -1), 0, 0, 0, 400)
    assert ans == OK and dur == 150.0
    # not alternating: two ups, a down first, a down before the end above, times backwards
    for t, d, a0, a1, what in (([1, 2, 3], [1, 1, -1], 0, 0, "up at t = 2 s after up"),
                               ([1, 2], [-1, 1], 0, 1, "down at t = 1 s after below"),
                               ([1, 2], [1, -1], 0, 1, "above the level after a downward"),
                               ([], [], 1, 0, "below the level after no crossing"),
                               ([2, 1], [1, -1], 0, 0, "after up at t = 2 s")):
        ans, dur, msg = pairs(t, d, a0, a1, 0, 6)
        assert ans == BAD and math.isnan(dur) and "do not" in msg and what in msg, (t, d)
    # cut off: above at the end, or at the start
    ans, dur, msg = pairs([1, 2, 3], [1, -1, 1], 0, 1, 0, 6)
    assert ans == CUT and math.isnan(dur) and "cut off at t_end" in msg and "t = 6 s" in msg
    ans, dur, msg = pairs([1, 2, 3], [-1, 1, -1], 1, 0, 0, 6)
    assert ans == CUT and math.isnan(dur) and "begun before the start" in msg


@pytest.mark.parametrize("periods", [3, 50])
def test_many_pulses_against_the_closed_form(oscillator, periods):
    """50 periods: 100 crossings (the driver once stopped at 64), each located
    on the solution: the time above 1 % of the peak is the closed form's."""
    sim, lib = oscillator
    T = 2 * math.pi / W
    t_end = (periods - 0.25) * T                      # s = -peak at the end: every pulse over
    values, codes, msgs = lib.summaries(sim.param_vector()[None], t_end, 1e-10, 1e-14)
    row = dict(zip(SUMMARY_KEYS, values[0]))
    assert codes[0] == 0 and msgs[0] == ""
    assert row["peak_pressure"] == pytest.approx(V0 / W, rel=1e-8)
    k = (row["time_of_peak"] - T / 4) / T           # every period's peak is as high
    assert abs(k - round(k)) < 1e-7
    exact = periods * (math.pi - 2 * math.asin(0.01)) / W
    assert row["pulse_duration"] == pytest.approx(exact, rel=1e-7)
    assert row["complete"] == 1.0
    # ending above the level (s = 0.8 of its peak, rising): no duration, not complete, said so
    values, codes, msgs = lib.summaries(sim.param_vector()[None], t_end + 0.4 * T, 1e-10, 1e-14)
    row = dict(zip(SUMMARY_KEYS, values[0]))
    assert codes[0] == 0 and "cut off at t_end" in msgs[0]
    assert math.isnan(row["pulse_duration"]) and row["complete"] == 0.0
    assert row["peak_pressure"] == pytest.approx(V0 / W, rel=1e-7)


def test_a_pulse_cut_off_by_t_end(paper):
    """The paper rig's pulse ends at about 12 ms: run to 8 ms, the peak (at
    5.57 ms) is reported, the duration and restitution are not; README's
    oil.n = 1.5 example is cut off at 20 ms and complete at 60 ms."""
    rig, sim = paper
    lib = sim.compiled()
    full, _, _ = lib.summaries(sim.param_vector()[None], 0.03, 1e-8, 1e-10)
    cut, codes, msgs = lib.summaries(sim.param_vector()[None], 0.008, 1e-8, 1e-10)
    full, cut = dict(zip(SUMMARY_KEYS, full[0])), dict(zip(SUMMARY_KEYS, cut[0]))
    assert codes[0] == 0 and full["complete"] == 1.0 and cut["complete"] == 0.0
    assert "cut off at t_end" in msgs[0] and "t = 0.008 s" in msgs[0]
    assert "contact continues" in msgs[0]
    for k in ("peak_pressure", "time_of_peak", "peak_contact_force"):
        assert cut[k] == pytest.approx(full[k], rel=1e-7), k
    assert math.isnan(cut["pulse_duration"]) and math.isnan(cut["restitution_coefficient"])
    P = sim.param_vector({"oil.n": 1.5})[None]
    short, codes, msgs = lib.summaries(P, 0.02, 1e-8, 1e-10)
    assert codes[0] == 0 and "cut off" in msgs[0]
    assert short[0, SUMMARY_KEYS.index("complete")] == 0.0
    assert math.isnan(short[0, SUMMARY_KEYS.index("pulse_duration")])
    long, codes, msgs = lib.summaries(P, 0.06, 1e-8, 1e-10)
    assert codes[0] == 0 and msgs[0] == "" and long[0, SUMMARY_KEYS.index("complete")] == 1.0
    res = rig.simulate(0.06, n_out=6001, params={"oil.n": 1.5}, backend="c")
    p = res["oil.pressure"]
    above = res.crossings("oil.pressure", 0.01 * long[0, 0])
    assert len(above) == 2 and p[-1] < 0.01 * p.max()       # one pulse, over by 60 ms
    assert long[0, SUMMARY_KEYS.index("pulse_duration")] == pytest.approx(above[1] - above[0],
                                                                         rel=1e-6)


def test_summaries_report_solver_statistics(paper):
    rig, sim = paper
    lib = sim.compiled()
    p = sim.param_vector()
    P = np.array([p, sim.param_vector({"hammer.v0": 4.23})])
    values, codes, msgs, stats = lib.summaries(P, 0.02, 1e-8, 1e-10, with_stats=True)
    _, run = lib.run(np.linspace(0, 0.02, 11), sim.start_vector(p), p, 1e-8, 1e-10)
    assert not codes.any() and len(stats) == 2
    for s in stats:
        assert set(s) == set(batch.STAT_KEYS) and s["method"] == "adams/fixed-point"
        assert s["rhs_evals"] >= s["steps"] > 0 and s["jac_evals"] == 0 and s["wall_time"] > 0
    # the same integration as run()'s, and the refinements' steps on top
    assert stats[0]["root_events"] == run.stats["root_events"] >= 5
    assert stats[0]["steps"] > run.stats["steps"]
    _, _, _, stats = lib.summaries(P[:1], 0.02, 1e-8, 1e-10, method="bdf", with_stats=True)
    assert stats[0]["method"] == "bdf/newton-dense" and stats[0]["jac_evals"] > 0


STACK_SCRIPT = """
import sys, threading
import numpy as np
from pdbfs.models import split_piston_rig
from pdbfs.simulation import Simulator
sim = Simulator.of(split_piston_rig(150))
lib = sim.compiled()
p = sim.param_vector()
t = np.linspace(0.0, 0.01, 101)
ref = lib.summaries(p[None], 0.01, 1e-8, 1e-10)[0]
X_ref = lib.run(t, sim.start_vector(p), p, 1e-8, 1e-10)[0]
threading.stack_size(128 * 1024)
out = {}
def work():
    out["summary"] = lib.summaries(p[None], 0.01, 1e-8, 1e-10)[0]
    out["run"] = lib.run(t, sim.start_vector(p), p, 1e-8, 1e-10)[0]
th = threading.Thread(target=work)
th.start()
th.join()
assert np.array_equal(out["summary"], ref, equal_nan=True) and np.array_equal(out["run"], X_ref)
print("same")
"""


def test_large_rigs_in_threads_with_small_stacks():
    """The drivers keep per-state arrays on the heap: a split piston of 305
    states summarised in a thread of 128 KiB stack gives the main thread's
    numbers (the driver with its arrays on the stack, 185 kB of them here,
    died of a segmentation fault in this test)."""
    import subprocess
    import sys
    r = subprocess.run([sys.executable, "-c", STACK_SCRIPT], capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0 and r.stdout.strip() == "same", (r.returncode, r.stderr[-2000:])
