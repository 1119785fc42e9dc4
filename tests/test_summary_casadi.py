"""The summary of a CasADi run at the cost of the run (issue 23): located on
the run's own solution when the grid is the summary's (nothing integrated
again, the rows it reads computed in one pass), agreeing with the compiled
backend's summary to the solvers' tolerance; crossings and impulses in
closed form (against polynomials whose answers are known); and the
simulation package free of import circles, function-local imports counted."""
import ast
import graphlib
import math
import pathlib
import warnings

import numpy as np
import pytest

from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator
from pdbfs.simulation.results import contact_impulse
from pdbfs.simulation.results.hermite import _one_root
from pdbfs.simulation.results.impulse import integral


@pytest.fixture(scope="module")
def rig():
    return paper_rig()


@pytest.mark.parametrize("params", [{}, {"hammer.v0": 5.5, "oil.k": 5e8}, {"hammer.v0": 1.5}])
def test_the_casadi_summary_agrees_with_the_compiled_one(rig, params):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        slow = rig.simulate(backend="casadi", params=params).summary()
        fast = rig.simulate(backend="c", method="adams", params=params).summary()
    assert list(slow) == list(fast)
    for k, v in fast.items():
        if k in ("time_of_peak", "pulse_duration"):       # times: to the solvers' 1e-8
            assert slow[k] == pytest.approx(v, rel=1e-6, abs=1e-8), k
        elif isinstance(v, float):
            assert slow[k] == pytest.approx(v, rel=1e-6), k
        else:
            assert slow[k] == v, k


def test_a_casadi_summary_on_the_runs_own_grid_integrates_nothing(rig, monkeypatch):
    res = rig.simulate(backend="casadi")
    sim = Simulator.of(rig)
    passes = []
    real = sim.rows_rates_events
    monkeypatch.setattr(sim, "integrate_shifted", lambda *a, **k: pytest.fail("integrated again"))
    monkeypatch.setattr(sim, "step", lambda *a, **k: pytest.fail("stepped again"))
    # the restitution's impulses: carried by the run itself (its quadrature)
    monkeypatch.setattr(contact_impulse, "on_grid", lambda *a, **k: pytest.fail("impulse again"))
    monkeypatch.setattr(sim, "rows_rates_events", lambda *a: passes.append(1) or real(*a))
    monkeypatch.setattr(sim, "outputs", lambda *a, **k: pytest.fail("a row computed alone"))
    monkeypatch.setattr(sim, "rates_on", lambda *a, **k: pytest.fail("a rate computed alone"))
    s = res.summary()
    assert s["complete"] is True and passes == [1]


def test_a_crossing_is_the_cubics_one_root():
    # (s - r)(s - 3)(s + 2): one root r in [0, 1]
    for r in (1e-9, 0.25, 0.5, 0.999999):
        c = np.polynomial.polynomial.polyfromroots([r, 3.0, -2.0])
        assert _one_root(*c) == pytest.approx(r, abs=1e-15)
    # three roots inside, or none: not one crossing
    assert _one_root(*np.polynomial.polynomial.polyfromroots([0.2, 0.5, 0.8])) is None
    assert _one_root(*np.polynomial.polynomial.polyfromroots([1.5, 2.0, -1.0])) is None
    # a root where the cubic turns (touching, not crossing, besides a crossing): not trusted
    assert _one_root(*np.polynomial.polynomial.polyfromroots([0.3, 0.6, 0.6])) is None


def test_impulses_are_exact_for_cubics_and_lines():
    t = np.sort(np.r_[0.0, np.random.default_rng(7).random(40), 2.0])
    y, dy = t ** 3 - 2 * t, 3 * t ** 2 - 2                 # a cubic: the Hermite one is exact
    F = lambda x: x ** 4 / 4 - x ** 2                       # noqa: E731
    for a, b in ((0.0, 2.0), (0.31, 1.7), (t[5], t[6]), (1.0, 1.0)):
        assert integral(t, y, a, b, dy) == pytest.approx(F(b) - F(a), abs=1e-13)
    assert integral(t, y, 1.7, 0.31, dy) == pytest.approx(F(0.31) - F(1.7), abs=1e-13)
    line = 3.0 * t - 1.0                                    # the trapezoidal rule is exact
    assert integral(t, line, 0.2, 1.9) == pytest.approx(1.5 * (1.9 ** 2 - 0.2 ** 2) - 1.7,
                                                       abs=1e-13)
    assert integral(t, y, -5.0, 9.0, dy) == pytest.approx(F(2.0), abs=1e-13)   # clipped
    assert math.isclose(integral(t, y, 0.5, 0.5, dy), 0.0)


def test_the_simulation_package_has_no_import_circle():
    here = pathlib.Path(__file__).resolve().parents[1] / "pdbfs" / "simulation"
    files = {f.relative_to(here).with_suffix("").as_posix().replace("/", "."): f
             for f in here.rglob("*.py")}
    graph = {}
    for name, f in files.items():
        deps, pkg = set(), name.split(".")[:-1]
        tree = ast.parse(f.read_text())
        typing_only = {id(n) for node in ast.walk(tree) if isinstance(node, ast.If)
                       and "TYPE_CHECKING" in ast.unparse(node.test)
                       for b in node.body for n in ast.walk(b)}     # annotations only: never run
        for node in ast.walk(tree):      # function-local imports too
            if isinstance(node, ast.ImportFrom) and node.level and id(node) not in typing_only:
                base = pkg[:len(pkg) - node.level + 1] + (node.module.split(".") if node.module else [])
                for a in node.names:      # a module of the package, else the module imported from
                    whole = ".".join(base + [a.name])
                    deps.add(whole if whole in files else ".".join(base) or "__init__")
        graph[name] = deps
    order = list(graphlib.TopologicalSorter(graph).static_order())   # CycleError if one
    assert order.index("results.summary_run") < order.index("results.summary") < \
        order.index("results.result")


def test_the_intervals_cubics_and_trust_are_those_of_the_whole_grid(rig):
    """Curves.interval (worked out per interval) against the whole-grid
    computation it replaced: the same coefficients, bit for bit, and the same
    trusted intervals (error estimate from the jumps of the third derivative)."""
    from pdbfs.simulation.results.hermite import TRUST, coefficients
    res = rig.simulate(backend="casadi")
    curves = res.curves
    for name in ("oil.pressure", "contact.fc", "hammer.v"):
        y, rate, _ = curves.data(name)
        c = coefficients(res.t, y, rate)
        h = np.diff(res.t)
        jump = np.abs(np.diff(6.0 * c[3] / h ** 3))
        err = np.zeros_like(h)
        err[:-1] = np.maximum(err[:-1], jump * h[:-1] ** 3 / 384)
        err[1:] = np.maximum(err[1:], jump * h[1:] ** 3 / 384)
        trusted = (err <= TRUST * np.max(np.abs(y))) & ~curves.kinks
        assert 0 < trusted.sum() < trusted.size          # both kinds occur
        for i in range(h.size):
            ci, ti = curves.interval(name, i)
            assert [float(v) for v in ci] == [float(m[i]) for m in c], (name, i)
            assert ti == bool(trusted[i]), (name, i)
