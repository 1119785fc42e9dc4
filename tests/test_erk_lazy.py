"""The explicit Runge-Kutta runs of a sweep and of rig.simulate() make a
step's dense output only where it is needed (PdbfsErk.lazy,
native/c/library/pdbfs_summary.c, native/c/library/pdbfs_run_summary.c): where an indicator nears a
root, for the steps the summary refines (made then from the stages the
record keeps), and for the output grid when the states are read. A sweep
point's summary is the one-run summary of rig.simulate(), the same numbers."""
import math
import os

import numpy as np
import pytest

import pdbfs
from pdbfs.models import RIGS
from pdbfs.simulation import Simulator


@pytest.mark.parametrize("name,param,values", [("paper", "hammer.v0", [1.6, 3.1, 5.4]),
                                               ("paper-hydraulic", "hammer.v0", [1.6, 3.1, 5.4]),
                                               ("hydraulic-pulse", "valve.A", [6e-5, 8e-5, 1e-4])])
def test_a_sweep_point_summary_is_the_one_run_summary(name, param, values):
    rig = RIGS[name]()
    res = pdbfs.sweep(rig, {param: values}, grid=False, progress=False)
    assert len(res) == len(values)
    compared = 0
    for pt, v in zip(res, values):
        one = rig.simulate(params={param: v})
        assert one.settings["method"] == "erk"
        s = one.summary()
        for key, got in pt.summary.items():
            want = s[key]
            if isinstance(want, float) and math.isfinite(want):
                assert got == pytest.approx(want, rel=1e-12, abs=0), (name, v, key)
                compared += 1
            else:
                assert got == want or (got != got and want != want), (name, v, key)
    assert compared >= 2 * len(values)


def test_the_sweep_skips_most_dense_outputs():
    """3 evaluations per step saved where no indicator nears a root (measured:
    3026 against 3611 evaluations on the paper rig), in a sweep and in
    rig.simulate() (its states on the grid made when first read) alike; a run
    that writes its grid as it goes makes every step's dense output"""
    rig = RIGS["paper"]()
    one = rig.simulate()
    sim = Simulator.of(rig)
    lib = sim.compiled()
    p = sim.param_vector(None)
    out, codes, _, stats = lib.summaries(p[None, :], 0.02, one.settings["rtol"], 1e-10, "erk",
                                         with_stats=True)
    X, st, values, *_ = lib.run_summary(one.t, sim.start_vector(p, None), p,
                                         one.settings["rtol"], 1e-10, "erk", keep=False)
    assert codes[0] == 0 and out[0][0] == one.summary()["peak_pressure"] == values[0]
    assert stats[0]["steps"] == one.stats["steps"] == st.steps          # the same steps,
    assert stats[0]["rhs_evals"] < 0.9 * st.rhs_evals                   # fewer evaluations
    assert one.stats["rhs_evals"] < 0.9 * st.rhs_evals
    assert np.array_equal(one["oil.pressure"], sim.outputs(one.t, X, np.zeros((0, one.t.size)),
                                                           p, [sim.dae.y_names.index("oil.pressure")])[0])


def test_the_states_are_made_once_when_read_at_any_size_of_the_record():
    """rig.simulate() keeps its run's record and makes the states on the grid
    when they are first read, once, whichever thread reads them; a record
    much larger than its grid of states (a long run, a coarse grid) too: a
    summary alone never makes them"""
    import threading
    rig = RIGS["paper"]()
    res = rig.simulate()
    assert res._states is None                      # nothing made yet
    got = []
    threads = [threading.Thread(target=lambda: got.append(res["oil.pressure"])) for _ in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert len(got) == 4 and all(np.array_equal(g, got[0]) for g in got)
    long = rig.simulate(0.2, n_out=11)
    assert long._states is None and long.stats["steps"] > 1000
    assert long.summary()["peak_pressure"] > 0 and long._states is None
    fine = rig.simulate(0.2, n_out=2001)
    assert np.array_equal(long["oil.pressure"], fine["oil.pressure"][::200])


def _rss_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return 0


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="reads /proc/self/status")
def test_a_kept_record_is_freed_with_its_result():
    """each kept run holds its record (about 0.2 MB for the paper rig) in the
    library's memory until its Result goes: 2,000 runs whose states are never
    read leave the process's resident memory where it was"""
    rig = RIGS["paper"]()
    for _ in range(50):
        rig.simulate().summary()
    before = _rss_bytes()
    for _ in range(2000):
        res = rig.simulate()
        assert res.summary()["peak_pressure"] > 0
    grown = _rss_bytes() - before
    assert grown < 50e6, f"resident memory grew by {grown / 1e6:.0f} MB"   # 2,000 records: 440 MB


NOWHERE = """
import ctypes, numpy as np
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
sim = Simulator.of(paper_rig())
lib = sim.compiled()
p = sim.param_vector(None); x0 = sim.start_vector(p, None); t = np.linspace(0, 0.02, 11)
info, out, code = np.zeros(8), np.zeros(8), np.zeros(1, np.intc)
msg, note = ctypes.create_string_buffer(512), ctypes.create_string_buffer(512)
# the explicit method (2) with neither X nor keep: no place for the states
rc = lib._run_summary(p.ctypes.data, x0.ctypes.data, t.size, t.ctypes.data, None, 5e-8, 1e-10, 2,
                      0.0, 1000, info.ctypes.data, msg, 512, out.ctypes.data, code.ctypes.data,
                      note, 512, None)
print(rc, msg.value.decode())
"""


def test_a_run_with_nowhere_for_its_states_is_refused_not_written_through():
    # a caller's mistake in the library's own API (every pdbfs path gives X or
    # keeps the run): an error code and its reason, never a crash
    import subprocess
    import sys
    run = subprocess.run([sys.executable, "-c", NOWHERE], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    rc, _, reason = run.stdout.strip().partition(" ")
    assert rc == "1" and "a buffer is missing" in reason
