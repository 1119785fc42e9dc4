"""method="auto" in the compiled backend: the modes of a new start by the
compiled library's C (native/c/pdbfs_modes.c, the FMU's code) rather than
CasADi's Jacobian and LAPACK, which took longer than the run itself. The two
must give the same modes and so the same choice; a loop over new parameters
must not grow the simulator's cache without end."""
import warnings

import numpy as np
import pytest

from pdbfs.models import RIGS
from pdbfs.simulation.simulator import Simulator
from pdbfs.simulation.stiffness import auto_method, fast_modes, rates

RIG_NAMES = ["paper", "paper-hydraulic", "hydraulic-pulse", "drop", "split-piston"]


@pytest.fixture(scope="module", params=RIG_NAMES)
def sim(request):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Simulator.of(RIGS[request.param]())


def test_the_compiled_modes_are_lapacks(sim):
    """Fastest modulus, fastest non-oscillating decay and fastest
    oscillating modulus, C against LAPACK,
    at the start and at a start with other parameters (the eigenvalues of
    the paper-hydraulic rig differ by 2e-7 between the two: the Jacobian's
    own sensitivity, not the code's)."""
    lib = sim.compiled()
    for scale in (1.0, 1.7):
        p = sim.param_vector(None) * scale
        x0 = sim.start_vector(p, None)
        c, ref = lib.modes(x0, p), rates(fast_modes(sim.dae, p, x0))
        assert c[0] == pytest.approx(ref[0], rel=1e-6)
        assert c[1] == pytest.approx(ref[1], rel=1e-6, abs=1e-9 * ref[0])
        assert c[2] == pytest.approx(ref[2], rel=1e-6, abs=1e-9 * ref[0])


@pytest.mark.parametrize("t_end", [0.02, 1.5])
def test_the_choice_is_the_same_either_way(sim, t_end):
    p = sim.param_vector(None)
    x0 = sim.start_vector(p, None)
    assert auto_method(sim.dae, p, x0, t_end, sim.compiled()) == auto_method(sim.dae, p, x0, t_end)


def test_a_jacobian_not_finite_at_the_start_has_no_modes_either_way():
    """A state at infinity (the contact's stiffness grows as sqrt(d)): no
    modes from either, and the same choice."""
    sim = Simulator.of(RIGS["paper"]())
    p = sim.param_vector(None)
    x0 = sim.start_vector(p, None)
    x0[0] = np.inf
    assert fast_modes(sim.dae, p, x0).size == 0
    assert sim.compiled().modes(x0, p) == (0.0, 0.0, 0.0)
    assert auto_method(sim.dae, p, x0, 0.02, sim.compiled()) == auto_method(sim.dae, p, x0, 0.02)


def test_a_loop_over_new_parameters_keeps_the_cache_bounded(monkeypatch):
    rig = RIGS["paper"]()
    sim = Simulator.of(rig)
    rig.simulate()
    monkeypatch.setattr(Simulator, "CACHE_MAX", len(sim._cache) + 3)
    peaks = [rig.simulate(params={"hammer.v0": 2.0 + 0.01 * i}).summary()["peak_pressure"]
             for i in range(10)]
    assert len(sim._cache) <= Simulator.CACHE_MAX + 1
    assert np.all(np.diff(peaks) > 0)          # each run its own, not a cached one
