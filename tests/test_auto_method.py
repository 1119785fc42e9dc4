"""method="auto" in the compiled backend: the modes of a new start by the
compiled library's C (native/c/shared/pdbfs_modes.c, the FMU's code) rather than
CasADi's Jacobian and LAPACK, which took longer than the run itself. The two
must give the same modes and so the same choice. A choice is made once per
class of runs (the values the estimate reads), is always the choice made
afresh, and a loop over new parameters must not grow the caches without end."""
import warnings

import numpy as np
import pytest

from pdbfs.models import RIGS
from pdbfs.simulation.run.simulator import Simulator
from pdbfs.simulation.run import stiffness
from pdbfs.simulation.run.stiffness import auto_method, estimate_inputs, fast_modes, rates

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


def test_a_loop_over_new_parameters_keeps_the_caches_bounded(monkeypatch):
    rig = RIGS["paper"]()
    sim = Simulator.of(rig)
    rig.simulate()
    monkeypatch.setattr(Simulator, "STARTS_MAX", 3)
    monkeypatch.setattr(stiffness, "AUTO_MAX", 4)
    peaks = [rig.simulate(params={"hammer.v0": 2.0 + 0.01 * i}).summary()["peak_pressure"]
             for i in range(10)]
    assert len(sim._starts) <= 3 and len(sim.state.auto) <= 4 + 1
    assert np.all(np.diff(peaks) > 0)          # each run its own, not a cached one


def _counting_modes(monkeypatch, lib):
    calls = []
    real = lib.modes
    monkeypatch.setattr(lib, "modes", lambda *a, **k: calls.append(1) or real(*a, **k))
    return calls


def test_the_estimate_reads_what_the_jacobian_depends_on():
    """The paper rig's d(ode)/dx does not depend on the starts' parameters or
    the oil's area (the pressure is an output), and does on the stiffnesses
    and masses; of the states, on the positions and speeds but the breech's
    speed."""
    dae = RIGS["paper"]().compile()
    ix, ip = estimate_inputs(dae)
    read = {dae.p_names[i] for i in ip}
    assert {"contact.k", "oil.k", "hammer.m", "seal.c", "mount.k"} <= read
    assert not read & {"hammer.v0", "hammer.s0", "piston.v0", "oil.A"}
    assert "hammer.v" in [dae.x_names[i] for i in ix]
    assert "breech.v" not in [dae.x_names[i] for i in ix]


def test_the_choice_is_made_once_per_class_of_runs_and_is_the_choice_made_afresh(monkeypatch):
    """A loop over a parameter the estimate does not read (the oil's area)
    asks for no modes after the first run; a loop over one it reads (the
    oil's stiffness) asks at each new value, and once only for a value
    repeated; a start moved in a state it reads asks again; every choice,
    cached or not, is auto_method's for that run; a seal ten thousand
    times as viscous (a fast mode that decays without oscillating) is a new
    class: BDF."""
    rig = RIGS["paper"]()
    sim = Simulator.of(rig)
    rig.simulate()
    lib = sim.compiled()
    calls = _counting_modes(monkeypatch, lib)
    for area in np.linspace(1e-3, 2e-3, 5):
        assert rig.simulate(params={"oil.A": area}).settings["method"] == "erk"
    assert not calls
    ks = np.array([0.5, 0.8, 1.2, 2.0, 50.0]) * sim.param_vector()[sim.dae.p_names.index("oil.k")]
    chosen = [rig.simulate(params={"oil.k": k}).settings["method"] for k in ks]
    assert len(calls) == 5
    for _ in range(3):                                 # the same parameters again: decided
        assert [rig.simulate(params={"oil.k": k}).settings["method"] for k in ks] == chosen
    assert len(calls) == 5
    s0 = sim.start_vector(sim.param_vector())[sim.x_names.index("hammer.s")]
    rig.simulate(start={"hammer.s": s0 - 1e-4})        # a new start: decided again, once
    rig.simulate(start={"hammer.s": s0 - 1e-4})
    assert len(calls) == 6
    stiff = rig.simulate(params={"seal.c": 2.556e8})
    assert stiff.settings["method"] == "bdf" and len(calls) == 7
    assert rig.simulate().settings["method"] == "erk" and len(calls) == 7
    for k, method in zip(ks, chosen):
        p = sim.param_vector({"oil.k": k})
        assert method == auto_method(sim.dae, p, sim.start_vector(p), 0.02, lib)[0]
