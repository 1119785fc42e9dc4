"""method="auto" in the compiled backend: the cheapest method by the cost
model of pdbfs.native.stiffness, checked against the methods' measured CPU
times on a few rigs and runs with a clear winner (each a case the choice by
radians of the fastest mode got wrong: Adams on the split piston and the bar
from 8 pieces, 2-4 times the explicit method's time; Adams on a long valve
run, 80 times BDF's). scripts/bench_auto.py measures every rig and size, at
equal accuracy."""
import re
import time
import warnings
from pathlib import Path

import pytest

from pdbfs.models import RIGS, bar_piston_rig, paper_rig, split_piston_rig
from pdbfs.native.stiffness import NEWTON_FROM, run_costs

FACTOR = 1.3
CASES = {"split-piston N=16": (lambda: split_piston_rig(n=16), 0.02, None),
         "bar-piston N=8": (lambda: bar_piston_rig(n=8), 0.02, None),
         "paper 0.5 s": (paper_rig, 0.5, None),
         "hydraulic-pulse 2 s": (RIGS["hydraulic-pulse"], 2.0, None),
         "paper seal.c=1e9": (paper_rig, 0.02, {"seal.c": 1e9})}


def cpu(rig, method, t_end, params):
    """CPU seconds of a run and its summary, as a user's run costs them."""
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rig.simulate(t_end, params=params, method=method, backend="c").summary()
    return time.process_time() - t


@pytest.mark.parametrize("label", list(CASES))
def test_auto_takes_a_method_within_1_3x_of_the_fastest(label):
    build, t_end, params = CASES[label]
    rig = build()
    chosen = rig.simulate(t_end, params=params, n_out=11, backend="c").settings["method"]
    times = {m: [] for m in ("erk", "adams", "bdf")}
    for m in times:                                    # warm: libraries, plans
        cpu(rig, m, t_end, params)
    for _ in range(3):                                 # interleaved: the machine's load shared
        for m in times:
            times[m].append(cpu(rig, m, t_end, params))
    best = {m: min(v) for m, v in times.items()}
    assert best[chosen] <= FACTOR * min(best.values()), (chosen, best)


def test_the_cost_model_prices_a_long_run_per_second():
    """With no run length (the FMU without a stop time) each method is priced
    per second of a long run: the per-run steps drop out, the rest scales."""
    modes = (7071.0, 105.8, 7071.0, 6, 97)
    one, long_run = run_costs(*modes, 1.0), run_costs(*modes, float("inf"))
    ten = run_costs(*modes, 10.0)
    for m in one:
        assert long_run[m] < one[m] and (ten[m] - one[m]) / 9 == pytest.approx(long_run[m], rel=1e-9)


def test_adams_newton_threshold_is_the_drivers():
    """The model's Adams uses Newton from the state count the C driver does."""
    header = (Path(__file__).parents[1] / "pdbfs/native/c/pdbfs_cvode.h").read_text()
    assert int(re.search(r"#define PDBFS_NEWTON_FROM (\d+)", header).group(1)) == NEWTON_FROM
