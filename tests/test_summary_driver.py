"""The compiled summary driver (pdbfs/native/c/library/pdbfs_summary.c): the same
summary as Result.summary(), located on the solution, for many points in one
call; generic over the rig's roles."""
import numpy as np
import pytest

import pdbfs
from pdbfs.models import paper_rig, split_piston_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled as batch
from pdbfs.simulation.run.compiled import SUMMARY_KEYS

POINTS = [{"hammer.v0": 1.87}, {"hammer.v0": 5.5}, {"seal.c": 2.556e6},
          {"oil.k": 8.228e8, "contact.D": 1.595e9}]


@pytest.fixture(scope="module")
def paper():
    rig = paper_rig()
    return rig, Simulator.of(rig)


def test_summaries_agree_with_result_summary(paper):
    """Peaks and crossings to 1e-6 of Result.summary(); the restitution
    (impulses integrated exactly here, on the output grid there) to 1e-6 of
    Result.summary() on a fine grid."""
    rig, sim = paper
    lib = sim.compiled()
    P = np.array([sim.param_vector(p) for p in POINTS])
    values, codes, _ = lib.summaries(P, 0.03, 1e-8, 1e-10)
    assert not codes.any() and lib.summary_keys == list(SUMMARY_KEYS)
    for row, params in zip(values, POINTS):
        res = rig.simulate(0.03, n_out=3001, params=params, backend="c")
        ref = res.summary()
        fine = rig.simulate(0.03, n_out=60001, params=params, backend="c").summary()
        # the stiff seal's pulse lasts beyond 30 ms: no duration, not complete
        cut = res["oil.pressure"][-1] > 0.01 * ref["peak_pressure"]
        assert cut == (params == {"seal.c": 2.556e6})
        assert row[SUMMARY_KEYS.index("complete")] == (0.0 if cut else 1.0)
        for i, k in enumerate(SUMMARY_KEYS):
            if k == "complete":
                assert ref[k] is (not cut)
                continue
            if cut and k == "pulse_duration":
                assert np.isnan(row[i]) and ref[k] is None
                continue
            if cut and k == "restitution_coefficient":
                assert ref[k] is None        # Result.summary(): not for a pulse cut off
                continue
            want = fine[k] if k == "restitution_coefficient" else ref[k]
            assert row[i] == pytest.approx(want, rel=1e-6), (params, k)


def test_a_tight_reference_is_met_better_than_by_the_grid_summary(paper):
    rig, sim = paper
    values, _, _ = sim.compiled().summaries(sim.param_vector()[None], 0.02, 1e-8, 1e-10)
    tight = rig.simulate(0.02, n_out=20001, rtol=1e-12, atol=1e-15).summary()
    for i, k in enumerate(SUMMARY_KEYS):
        if k != "complete":
            assert values[0, i] == pytest.approx(tight[k], rel=1e-6), k


def test_failures_and_undefined_values_per_point(paper):
    rig, sim = paper
    P = np.array([sim.param_vector(), sim.param_vector({"hammer.v0": 0.0}),
                  sim.param_vector(), sim.param_vector({"hammer.v0": 1e-9})])
    P[2, sim.dae.p_names.index("contact.k")] = np.nan            # not finite: that point fails
    values, codes, msgs = sim.compiled().summaries(P, 0.02, 1e-8, 1e-10)
    assert codes[0] == 0 and codes[2] != 0 and "not finite" in msgs[2]
    assert np.all(np.isfinite(values[0])) and np.all(np.isnan(values[2])) and msgs[0] == ""
    # a hammer at rest: no contact, no pulse: no restitution (NaN, None in Python), not complete
    row = dict(zip(SUMMARY_KEYS, values[1]))
    assert codes[1] == 0 and np.isnan(row["restitution_coefficient"]) and row["complete"] == 0
    assert np.isnan(row["peak_pressure"]) and "no pressure pulse" in msgs[1]   # no peak
    # a hammer that hardly moves (1 nm/s): a pressure of mPa, at the size of the solver's
    # error at atol 1e-10 m, whose crossings integrated again are others: a failure, no numbers
    assert codes[3] == batch.RC_BAD_CROSSINGS and "not resolved" in msgs[3]
    assert np.all(np.isnan(values[3]))


def test_other_rigs_and_the_sweep_use_it(paper):
    rig = split_piston_rig(n=3)
    res = pdbfs.sweep(rig, {"hammer.v0": [2.0, 4.0]}, backend="c", workers=1)
    assert res.where == "this process"
    for pt in res:
        ref = rig.simulate(0.02, params=pt.params, backend="c").summary()
        for k in ("peak_pressure", "pulse_duration", "peak_contact_force"):
            assert pt.summary[k] == pytest.approx(ref[k], rel=1e-6), k


def test_result_summary_is_the_same_on_coarse_and_fine_grids(paper):
    """The Hermite interpolant serves where it is trusted, root finding on the
    solution elsewhere: the summary does not depend on the output grid (as
    long as the grid sees the right hump of a many-humped force: 50 us here)."""
    rig, _ = paper
    fine = rig.simulate(0.02, n_out=8001).summary()
    for n in (401, 2001):
        coarse = rig.simulate(0.02, n_out=n).summary()
        for k, v in fine.items():
            assert coarse[k] == pytest.approx(v, rel=3e-6), (n, k)
