"""Large rigs (issue 10): no cap on the number of masses, the integrator
chosen for the structure (method='auto'), the band linear solver of the
compiled backend and the FMU, and clear errors where a rig is too large for
the compiler. Times are benchmarks (scripts/bench_scale.py), not tests."""
import ctypes
import warnings

import casadi as ca
import numpy as np
import pytest

import pdbfs
from pdbfs.components import Damper, Fixed, Mass, Spring
from pdbfs.errors import ExportError, ParameterError
from pdbfs.models import paper_rig, split_piston_rig
from pdbfs.native import codegen
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled as batch
from pdbfs.simulation.run.stiffness import choose_method

ADAMS, BDF = 0, 1
NEWTON = 2 << 4
DENSE, BAND = 1 << 8, 2 << 8


class Overdamped(pdbfs.Rig):
    """A mass on a soft spring behind a very strong damper: the damper's mode
    decays at c/m = 1e8 1/s without oscillating, the spring's at k/c: stiff."""
    name = "overdamped"

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=1e-3, v0=1.0)
        self.spring = Spring(k=1e4)
        self.damper = Damper(c=1e5)
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.body.flange_a)


@pytest.mark.parametrize("n", [0, -2, 2.5, True, "4"])
def test_a_piece_count_below_one_is_refused(n):
    with pytest.raises(ParameterError, match="n = .* whole number"):
        split_piston_rig(n)


def test_hundreds_of_pieces_build_and_reproduce_the_paper_pulse():
    """No cap on n: 400 pieces (804 states) compile; the piston is 16 times
    stiffer than the oil, so the pressure pulse stays the paper rig's."""
    rig = split_piston_rig(400)
    dae = rig.compile()
    assert dae.x.numel() == 2 * 400 + 4 and dae.is_ode
    r = rig.simulate(0.012, n_out=241)
    ref = paper_rig().simulate(0.012, n_out=241)
    assert r.peak("oil.pressure")[1] == pytest.approx(ref.peak("oil.pressure")[1], rel=0.03)
    assert r.peak("oil.pressure")[0] == pytest.approx(ref.peak("oil.pressure")[0], rel=0.1)


def test_auto_keeps_adams_on_the_paper_rig_and_its_results():
    dae = paper_rig().compile()
    sim = Simulator.of(dae)
    p = sim.param_vector()
    assert choose_method(dae, p, sim.start_vector(p), 0.02)[0] == "adams"
    # through CasADi "auto" is Adams itself (compiled, it is the explicit method: test_erk.py)
    auto, adams = (pdbfs.simulate(dae, method=m, backend="casadi")["oil.pressure"]
                   for m in ("auto", "adams"))
    assert np.array_equal(auto, adams)


def test_auto_picks_bdf_for_a_fast_decaying_mode_and_bdf_is_cheaper_there():
    dae = Overdamped().compile()
    sim = Simulator.of(dae)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    method, why = choose_method(dae, p, x0, 0.05)
    assert method == "bdf" and "without oscillating" in why
    grid = np.linspace(0.0, 0.05, 101)
    c = batch.compiled(dae)
    steps = {}
    for name, code in (("adams", ADAMS | NEWTON), ("bdf", BDF)):
        X, st = c.run(grid, x0, p, 1e-8, 1e-10, method=name)
        assert st.ok
        steps[name] = st.steps
        # overdamped: x(t) -> 0 along the slow mode exp(-k t / c)
        assert abs(X[0, -1]) < 1e-6
    assert steps["bdf"] * 10 < steps["adams"]
    r = pdbfs.simulate(dae, 0.05, n_out=101, method="auto")
    assert r.settings["method"] == "bdf"


def test_an_oscillating_chain_is_not_called_stiff():
    """The split piston's fastest modes ring (|Im| >> |Re|): through CasADi,
    Adams, whose steps are fewer than BDF's there."""
    dae = split_piston_rig(50).compile()
    sim = Simulator.of(dae)
    p = sim.param_vector()
    method, why = choose_method(dae, p, sim.start_vector(p), 0.02)
    assert method == "adams" and why.startswith("the cheapest by the estimate (adams")


def test_the_band_solver_of_the_compiled_backend_agrees_with_dense_lu():
    """A chain's Jacobian is banded: the C driver picks a band LU by itself
    (the same numbers as asking for it) and agrees with dense LU to the
    tolerance."""
    rig = split_piston_rig(30)
    dae = rig.compile()
    sim = Simulator.of(dae)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    c = batch.compiled(dae)
    grid = np.linspace(0.0, 0.012, 241)
    out = {}
    for name, code in (("auto", BDF), ("band", BDF | BAND), ("dense", BDF | DENSE),
                       ("adams-band", ADAMS | NEWTON | BAND)):
        X = np.empty((c.nx, grid.size))
        info = np.zeros(batch.INFO_N)
        rc = c._run(c.nx, c.np, p.ctypes.data, x0.ctypes.data, grid.size, grid.ctypes.data,
                    X.ctypes.data, 1e-8, 1e-10, code, 0.0, 500000, info.ctypes.data, None, 0)
        assert rc == 0, name
        out[name] = X
    assert np.array_equal(out["auto"], out["band"])
    i = dae.x_names.index("breech.s")
    scale = np.abs(out["dense"][i]).max()
    assert np.abs(out["band"][i] - out["dense"][i]).max() < 1e-5 * scale
    assert np.abs(out["adams-band"][i] - out["dense"][i]).max() < 1e-5 * scale
    # 64 states: the C driver integrates through the roots, as CasADi's CVODES does
    p_c = rig.simulate(0.012, n_out=241, backend="c")["oil.pressure"]
    p_casadi = rig.simulate(0.012, n_out=241)["oil.pressure"]
    assert np.abs(p_c - p_casadi).max() < 1e-6 * p_casadi.max()


def test_the_compiled_driver_refuses_an_unknown_solver_code():
    dae = paper_rig().compile()
    c = batch.compiled(dae)
    sim = Simulator.of(dae)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    X, grid, info = np.empty((c.nx, 2)), np.array([0.0, 1e-3]), np.zeros(batch.INFO_N)
    msg = ctypes.create_string_buffer(200)
    rc = c._run(c.nx, c.np, p.ctypes.data, x0.ctypes.data, 2, grid.ctypes.data, X.ctypes.data,
                1e-8, 1e-10, 3 << 8, 0.0, 100, info.ctypes.data, msg, 200)
    assert rc == batch.RC_BAD_INPUT and "solver code 768" in msg.value.decode()


def test_c_too_large_for_the_free_memory_is_refused_before_compiling(tmp_path):
    c = tmp_path / "big.c"
    c.write_text("/* generated */\n" * 100_000)
    with pytest.raises(ExportError, match=r"the FMU binary of rig big: the generated C is 1\.6 MB"
                                          r".*GB of memory but .*fewer masses"):
        codegen.check_compiler_memory(c, "the FMU binary of rig big", available=10**8)
    codegen.check_compiler_memory(c, "the FMU binary of rig big", available=10**12)


@pytest.mark.parametrize("which", ["ode", "jac", "out"])
def test_large_functions_are_generated_in_parts_that_compute_the_same(which):
    """GCC's optimisation grows faster than linearly with one function's
    size: a large model function becomes parts of bounded size, called by a
    function of the same name, inputs and output sparsity."""
    dae = split_piston_rig(60).compile()
    (f,) = codegen.model_functions(dae, (which,))
    g = codegen.split(f, size=500)
    assert f.n_instructions() > 2000
    parts = [g.instruction_MX(k) for k in range(g.n_instructions())
             if g.instruction_id(k) == ca.OP_CALL]
    assert len(parts) >= f.n_instructions() // 500
    assert all(p.which_function().n_instructions() <= 2 * 500 for p in parts)
    assert g.name() == f.name() and g.sparsity_out(0) == f.sparsity_out(0)
    rng = np.random.default_rng(1)
    args = [rng.normal(size=f.sparsity_in(i).shape) for i in range(f.n_in())]
    assert np.allclose(g(*args).full(), f(*args).full(), rtol=1e-14, atol=0)
    assert codegen.split(codegen.model_functions(paper_rig().compile(), ("ode",))[0]).is_a(
        "SXFunction")                                   # small: left whole


def test_a_compiler_killed_midway_is_a_clear_error():
    with pytest.raises(ExportError, match="killed by signal 9 .*out of memory"):
        codegen.run_compiler(["sh", "-c", "kill -9 $$"], "the FMU binary of rig big")


def test_simulate_warns_when_the_bar_segments_are_coarser_than_the_output():
    from pdbfs.components import BarResolutionWarning
    from pdbfs.models import RIGS, bar_piston_rig
    with pytest.warns(BarResolutionWarning, match=r"'piston'.* 5\.24 times the output interval "
                                                  r"5e-06 s; use n >= 53"):
        bar_piston_rig(10).simulate(0.01, n_out=2001)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BarResolutionWarning)
        RIGS["bar-piston"]().simulate(0.012, n_out=1201)     # 30 segments: resolved
        # a longer bar (params=) has slower segments: warned again
        with pytest.raises(BarResolutionWarning, match="piston"):
            RIGS["bar-piston"]().simulate(0.012, n_out=1201, params={"piston.L": 3.0})


@pytest.mark.parametrize("method", ["bdf", "adams"])
def test_the_summary_run_of_a_long_chain_takes_the_band_solver_and_agrees_with_dense(
        method, monkeypatch):
    """The run a simulate makes (the states and the contact's impulse, whose
    row is far from the diagonal): band LU for the chain at N = 64, with the
    same states and pulse as dense LU to the tolerance; dense for the paper rig."""
    rig = split_piston_rig(64)
    sim = Simulator.of(rig)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    c = sim.compiled(method)
    grid = np.linspace(0.0, 0.02, 401)
    out = {}
    for name, linsol in (("auto", 0), ("dense", DENSE)):
        monkeypatch.setitem(batch.METHOD_CODES, method, batch.METHOD_CODES[method] | NEWTON | linsol)
        X, st, values, code, _, _ = c.run_summary(grid, x0, p, 1e-8, 1e-10, method)
        assert st.ok and code == 0
        out[name] = (X, st.stats["method"], dict(zip(batch.SUMMARY_KEYS, values)))
    assert out["auto"][1] == f"{method}/newton-band" and out["dense"][1] == f"{method}/newton-dense"
    i = rig.compile().x_names.index("breech.s")
    scale = np.abs(out["dense"][0][i]).max()
    assert np.abs(out["auto"][0][i] - out["dense"][0][i]).max() < 1e-5 * scale
    for key in ("peak_pressure", "pulse_duration", "peak_contact_force"):
        assert out["auto"][2][key] == pytest.approx(out["dense"][2][key], rel=1e-5), key
    paper = Simulator.of(paper_rig())
    pp = paper.param_vector()
    monkeypatch.setitem(batch.METHOD_CODES, method, batch.METHOD_CODES[method] & 15 | NEWTON)
    _, st, *_ = paper.compiled(method).run_summary(grid, paper.start_vector(pp), pp, 1e-8, 1e-10,
                                                   method)
    assert st.ok and st.stats["method"] == f"{method}/newton-dense"
