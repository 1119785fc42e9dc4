"""The Python around a run: what depends on the rig alone (its default
parameter and start vectors, the grid of a (t_end, n_out), settings that
passed, its output checks, "auto"'s choice for a class of runs) is made and
checked once and kept in the rig's state; what a caller gives is checked
every time; nothing cached leaks from one run into the next; every run, with
options or without, takes the one path, so a loop over new parameters costs
about what the rig's own run costs (its speed against hand-written C is a
benchmark's target: bench_simulate)."""
import math
import sys
import time

import numpy as np
import pytest

from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig
from pdbfs.simulation import Simulator


@pytest.fixture(scope="module")
def rig():
    r = paper_rig()
    r.simulate().summary()       # built, loaded, every cache filled
    return r


def _calls(fn):
    """The Python functions called by ``fn()`` (file:name of each call)."""
    seen = []

    def prof(frame, event, arg):
        if event == "call":
            seen.append(f"{frame.f_code.co_filename.rsplit('/', 1)[-1]}:{frame.f_code.co_name}")
    sys.setprofile(prof)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return seen


def test_a_default_run_and_its_summary_do_the_rig_s_work_once(rig):
    # walking the component tree, building the grid, the CasADi start function,
    # the component conditions, the summary's keys, the modes of "auto":
    # done by the first run only, and for parameters given again by their first run
    rig.simulate(params={"oil.k": 3e8}).summary()
    for run in (lambda: rig.simulate().summary(),
                lambda: rig.simulate(params={"oil.k": 3e8}).summary()):
        calls = _calls(run)
        for once in ("component.py:walk", "function_base.py:linspace",
                     "dae.py:check_conditions", "dae.py:p_default", "summary.py:keys_for",
                     "dae.py:function", "summary_run.py:summary_run", "compiled.py:modes",
                     "settings.py:check_settings"):
            assert once not in calls, once


def test_a_loop_over_parameters_costs_about_what_the_rig_s_own_run_costs(rig):
    """One path for every run: a run with the same params= each time, and
    one with a new hammer velocity each time (nothing of the run before can
    be reused but what the rig alone decides), each take at most 1.4 times
    the CPU time of the rig's own run (medians of interleaved batches; a
    loose bound under load: the targets and figures are bench_run_overhead's)."""
    v = [2.0]

    def new_params():
        v[0] = float(np.nextafter(v[0], 3.0))
        return rig.simulate(params={"hammer.v0": v[0]}).summary()
    runs = {"own": lambda: rig.simulate().summary(),
            "same": lambda: rig.simulate(params={"hammer.v0": 2.0}).summary(),
            "new": new_params}
    times = {k: [] for k in runs}
    for f in runs.values():
        f()
    for r in range(60):
        for k in list(runs)[r % 3:] + list(runs)[:r % 3]:
            t = time.process_time()
            for _ in range(5):
                runs[k]()
            times[k].append(time.process_time() - t)
    for k in ("same", "new"):
        ratio = np.median(times[k]) / np.median(times["own"])
        assert ratio < 1.4, f"a run with {k} params= takes {ratio:.2f}x the rig's own run"


def test_a_run_never_sees_what_an_earlier_one_was_given_or_changed(rig):
    default = rig.simulate()
    v0 = default.params["hammer.v0"]
    faster = rig.simulate(params={"hammer.v0": v0 + 1.0}, start={"hammer.s": 0.0})
    assert faster.params["hammer.v0"] == v0 + 1.0
    # the caller's arrays are the caller's: changing them changes no later run
    default.t[:] = 7.0
    default.p[:] = 7.0
    again = rig.simulate()
    assert again.params["hammer.v0"] == v0
    assert again.t[0] == 0.0 and again.t[-1] == pytest.approx(0.02, rel=1e-15)
    assert np.array_equal(again.t, np.linspace(0.0, 0.02, 2001))
    assert again.summary()["peak_pressure"] < faster.summary()["peak_pressure"]
    assert again.summary()["peak_pressure"] == rig.simulate().summary()["peak_pressure"]


def test_a_grid_given_stays_the_caller_s(rig):
    """A run on a t_out of the caller's keeps its own copy: the caller's
    array stays writable, and changing it changes neither the Result's times
    nor its values off the grid."""
    t = np.linspace(0.0, 0.02, 401)
    res = rig.simulate(t_out=t)
    assert t.flags.writeable
    t[:] = 7.0
    assert res.t[0] == 0.0 and res.t[-1] == 0.02
    again = rig.simulate(t_out=np.linspace(0.0, 0.02, 401))
    assert res.value_at("piston.s", 0.01005) == again.value_at("piston.s", 0.01005)


def test_a_strided_grid_gives_the_states_of_the_same_grid_made_contiguous(rig):
    # a kept grid goes to C by its address; any other grid is made
    # contiguous first (a strided t_out read as it lies would be other times)
    fine = np.linspace(0.0, 0.02, 801)
    strided, whole = rig.simulate(t_out=fine[::4]), rig.simulate(t_out=fine[::4].copy())
    assert not fine[::4].flags.c_contiguous
    assert np.array_equal(strided.t, whole.t)
    assert np.array_equal(strided["piston.s"], whole["piston.s"])
    assert strided.summary() == whole.summary()
    # and runs on the kept grid agree with a run on a grid of the caller's
    default, given = rig.simulate(), rig.simulate(t_out=np.linspace(0.0, 0.02, 2001))
    assert np.array_equal(default["piston.s"], given["piston.s"])


@pytest.mark.parametrize("kwargs, culprit", [
    ({"params": {"hammer.v0": float("nan")}}, "hammer.v0"),
    ({"params": {"hammer.vv0": 3.0}}, "hammer.vv0"),
    ({"start": {"hammer.s": math.inf}}, "hammer.s"),
    ({"rtol": "1e-8"}, "rtol"),
    ({"atol": -1.0}, "atol"),
    ({"max_num_steps": True}, "max_num_steps"),
    ({"n_out": 1}, "n_out"),
    ({"t_end": float("nan")}, "t_end"),
    ({"t_out": [0.0, 0.01, 0.005]}, "t_out"),
])
def test_bad_input_after_good_runs_is_still_refused_in_one_line(rig, kwargs, culprit):
    rig.simulate(max_num_steps=1000, n_out=11)      # good settings remembered first
    kw = dict(kwargs)
    t_end = kw.pop("t_end", 0.02)
    with pytest.raises(ParameterError) as err:
        rig.simulate(t_end, **kw)
    assert culprit in str(err.value) and "\n" not in str(err.value)


def test_remembered_settings_are_keyed_with_their_types(rig):
    sim = Simulator.of(rig)
    sim.settings_ok(1e-8, 1e-10, "adams", None, 1, "c")
    with pytest.raises(ParameterError, match="max_num_steps"):
        sim.settings_ok(1e-8, 1e-10, "adams", None, True, "c")     # True == 1, but no number
    with pytest.raises(ParameterError, match="rtol"):
        sim.settings_ok([1e-8], 1e-10, "adams", None, 10, "c")    # unhashable: checked


def test_the_initial_record_of_a_declared_start_is_the_start(rig):
    res = rig.simulate(start={"hammer.s": 1e-4})
    assert res.initial["hammer.s"] == 1e-4
    assert res.initial.values == dict(zip(Simulator.of(rig).x_names, res._X[:, 0].tolist()))
    assert res.initial.solved == []


def test_output_checks_are_found_again_when_the_rig_is_compiled_again():
    r = paper_rig()
    r.simulate(n_out=11)
    assert r._output_checks() == []
    seen = []
    r.hammer.check_output = lambda dt, params: seen.append(dt)
    object.__setattr__(r, "_compiled", None)     # as connect() and free() leave a changed rig
    r.simulate(0.01, n_out=11)
    r.simulate(0.01, n_out=101)
    assert seen == [pytest.approx(1e-3), pytest.approx(1e-4)]


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_a_run_and_its_summary_leave_no_reference_cycle(rig, backend):
    import gc
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rig.simulate(backend=backend).summary()
        gc.collect()
        was = gc.get_debug()
        gc.set_debug(gc.DEBUG_SAVEALL)
        try:
            for _ in range(3):
                rig.simulate(backend=backend).summary()
                rig.simulate(0.005, n_out=501, backend=backend).summary()   # summary.py's path
            gc.collect()
            # pdbfs's objects and arrays (ctypes keeps cycles of its own array types)
            left = [type(o).__name__ for o in gc.garbage
                     if type(o).__module__.startswith("pdbfs") or isinstance(o, np.ndarray)]
        finally:
            gc.set_debug(was)
            gc.garbage.clear()
    assert not left, sorted(set(left))


def test_the_components_conditions_are_checked_on_every_run():
    from pdbfs.models import RIGS
    rig = RIGS["hydraulic-pulse"]()
    rig.simulate(0.001, n_out=3)                     # the defaults pass, and are remembered
    t_close = next(q.value for q in rig.compile().params if q.name == "valve.t_close")
    with pytest.raises(ParameterError, match="valve.t_open") as err:
        rig.simulate(0.001, n_out=3, params={"valve.t_open": 2 * t_close})
    assert "close before it opens" in str(err.value) and "\n" not in str(err.value)
    rig.simulate(0.001, n_out=3)                     # and the defaults still pass


@pytest.mark.parametrize("name", ["paper", "paper-hydraulic", "hydraulic-pulse", "drop"])
def test_new_parameters_take_their_start_and_conditions_from_the_library(name):
    """A loop over new parameters (calibration by hand, a user's own sweep)
    takes each run's start values and the components' conditions from the
    compiled library (pdbfs_batch_start): bitwise the DAE's own CasADi
    functions, at the defaults and at points around them; and a run whose
    parameters break a condition is still refused, naming it."""
    import casadi as ca
    from pdbfs.models import RIGS
    rig = RIGS[name]()
    rig.simulate(0.001, n_out=3)
    sim = Simulator.of(rig)
    dae, lib = sim.dae, sim.compiled()
    assert sim.numeric("start", None) == lib.start
    conds = ca.Function("c", [dae.p], [ca.vertcat(*[e for e, _ in dae.conditions])]) \
        if dae.conditions else None
    rng = np.random.default_rng(3)
    p0 = sim.param_vector(None)
    for k in range(6):
        p = p0 * (rng.uniform(0.5, 2.0, p0.size) if k else 1.0)
        assert np.array_equal(lib.start(p), dae.function("start")(p).full().ravel())
        if conds is not None:
            assert sim.numeric("conditions", None) == lib.conditions
            assert np.array_equal(lib.conditions(p), conds(p).full().ravel())
    assert lib.nc == len(dae.conditions)
    with pytest.raises(ParameterError, match="parameters given"):
        lib.start(p0[:-1])


def _same_run(a, b):
    assert a.summary() == b.summary()
    assert np.array_equal(a.t, b.t) and np.array_equal(a.p, b.p)
    for name in a.names:
        assert np.array_equal(a[name], b[name]), name
    assert a.settings == b.settings and a.initial == b.initial
    assert {k: v for k, v in a.stats.items() if k != "wall_time"} == \
        {k: v for k, v in b.stats.items() if k != "wall_time"}
    assert list(a.stats) == list(b.stats)


@pytest.mark.parametrize("t_end, n_out", [(0.02, 2001), (0.0015, 2001), (0.02, 3)])
def test_a_run_again_is_the_run_on_a_grid_of_the_caller_s(rig, t_end, n_out):
    """rig.simulate() again with its settings kept (the grid of a (t_end,
    n_out), read-only, the rig's own start) gives every number, setting and
    statistic of a run on the same grid given as t_out (made and checked
    anew), a pulse cut off at t_end included, whose summary warns either
    way, and a run whose record outweighs its grid."""
    import warnings
    rig.simulate(t_end, n_out=n_out)
    general = rig.simulate(t_end, t_out=np.linspace(0.0, t_end, n_out))
    with warnings.catch_warnings(record=True) as w_again:
        warnings.simplefilter("always")
        again = rig.simulate(t_end, n_out=n_out)
        s_again = again.summary()
    with warnings.catch_warnings(record=True) as w_general:
        warnings.simplefilter("always")
        s_general = general.summary()
    assert s_again == s_general
    assert [str(w.message) for w in w_again] == [str(w.message) for w in w_general]
    assert (t_end < 0.01) == bool(w_again) == (not s_again["complete"])
    _same_run(again, general)


def test_a_compiled_run_that_fails_says_why_in_one_line(rig, monkeypatch):
    """A run whose compiled call fails raises a SolverError of one line; the
    next run, the call mended, is the rig's run again."""
    from pdbfs.errors import SolverError
    from pdbfs.simulation.run import compiled as C
    rig.simulate()
    lib = Simulator.of(rig).compiled()
    real = lib._run_summary

    def failing(*a):
        real(*a)
        return C.RC_NOT_FINITE
    monkeypatch.setattr(lib, "_run_summary", failing)
    with pytest.raises(SolverError) as err:
        rig.simulate()
    assert "\n" not in str(err.value)
    monkeypatch.setattr(lib, "_run_summary", real)
    assert rig.simulate().summary() == rig.simulate(t_out=np.linspace(0, 0.02, 2001)).summary()


def test_a_new_parameter_list_is_the_rig_s_own_run_at_once():
    """A rig whose parameter list is replaced (new defaults) makes its own
    start again under the same settings: its runs read the kept grid, and
    give the new defaults' run, never the old one's."""
    import dataclasses
    import gc
    rig = paper_rig()
    dae = rig.compile()
    first = rig.simulate(0.003)
    rig.simulate(0.003)                                   # the settings and own start kept
    old = dae.params
    try:
        dae.params = [dataclasses.replace(q, value=q.value * 1.1) if q.name == "hammer.v0" else q
                      for q in old]
        made = rig.simulate(0.003)                        # the new own start, made
        gc.collect()                                      # the first start's arrays: gone,
        junk = [np.linspace(0.0, 0.005, 2001) for _ in range(64)]   # their memory reused
        again = rig.simulate(0.003)                       # the new own start, kept
        del junk
        assert again.params["hammer.v0"] == made.params["hammer.v0"] == \
            1.1 * first.params["hammer.v0"]
        assert again.summary() == made.summary() != first.summary()
        assert np.array_equal(again.t, first.t)
        assert np.array_equal(again["oil.pressure"], made["oil.pressure"])
    finally:
        dae.params = old
    assert rig.simulate(0.003).summary() == first.summary()


def test_threads_running_the_rig_each_get_their_own_run(rig):
    """The compiled call's arguments are per thread (each its own answer
    buffer) and the kept parameters, start and grid are only read: runs in
    parallel threads are each the run alone, statistics included."""
    from concurrent.futures import ThreadPoolExecutor
    alone = rig.simulate()
    with ThreadPoolExecutor(4) as pool:
        runs = list(pool.map(lambda _: rig.simulate(), range(64)))
    for r in runs:
        assert r.summary() == alone.summary()
        assert {k: v for k, v in r.stats.items() if k != "wall_time"} == \
            {k: v for k, v in alone.stats.items() if k != "wall_time"}
    assert np.array_equal(runs[-1]["oil.pressure"], alone["oil.pressure"])


def test_a_block_unpacks_what_its_views_read(rig):
    """Block.unpack reads info, the summary's values, its code, the note's
    first byte and the kept run's handle from the offsets the views use."""
    lib = Simulator.of(rig).compiled()
    b = lib._block()
    b.buf[:] = np.arange(b.buf.size) + 0.5
    b.code[0] = -7
    b.note[0] = 65
    b.handle[0] = 2**63 + 12345
    a = b.unpack(b.bytes)
    n_info, n_out = b.info.size, b.out.size
    assert list(a[:n_info]) == b.info.tolist() and list(a[n_info:n_info + n_out]) == b.out.tolist()
    assert a[n_info + n_out:] == (-7, 65, 2**63 + 12345)
    addr = b.buf.ctypes.data
    assert b.addr[2] == addr + 8 * (b.p.size + b.x0.size) == b.info.ctypes.data
    b.buf[:] = 0.0
    assert (b.addr[3], b.addr[5], b.addr[6]) == (b.msg.ctypes.data, b.code.ctypes.data,
                                               b.note.ctypes.data)


@pytest.mark.parametrize("name, pname", [("paper", "hammer.v0"), ("paper-hydraulic-oil", "contact.k"),
                                         ("split-piston", "hammer.v0")])
def test_new_parameters_under_kept_settings_are_the_run_on_a_given_grid(name, pname):
    """rig.simulate(params=...) again under the same settings (kept: the
    grid, the checks) with the new parameters checked, their start and the
    method chosen for them: the same numbers, settings and statistics as a
    run with its grid given."""
    import warnings
    from pdbfs.models import RIGS
    rig = RIGS[name]()
    base = next(q.value for q in rig.compile().params if q.name == pname)
    grid = np.linspace(0.0, 0.02, 2001)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rig.simulate(params={pname: base})
        for f in (1.01, 0.97, 1.05):
            again = rig.simulate(params={pname: base * f})
            general = rig.simulate(params={pname: base * f}, t_out=grid)
            _same_run(again, general)
            assert again.params[pname] == base * f


def test_new_parameters_that_need_another_method_get_it():
    """New parameters that make the rig stiff (a seal ten thousand times as
    viscous: BDF, 3x faster than the explicit method there) are integrated
    by the method chosen for them, exactly as a run on a grid of its own."""
    rig = paper_rig()
    assert rig.simulate(params={"seal.c": 2.556e4}).settings["method"] == "erk"
    stiff = rig.simulate(params={"seal.c": 2.556e8})
    general = rig.simulate(params={"seal.c": 2.556e8}, t_out=np.linspace(0.0, 0.02, 2001))
    assert stiff.settings["method"] == general.settings["method"] == "bdf"
    _same_run(stiff, general)


def test_settings_kept_are_found_by_their_types_too(rig):
    """The settings a run kept are found by their values and types: a float
    where a count belongs is refused after a run with the count."""
    rig.simulate(0.02, n_out=11)
    with pytest.raises(ParameterError, match="n_out") as err:
        rig.simulate(0.02, n_out=11.0)
    assert "\n" not in str(err.value)
    rig.simulate(0.02, max_num_steps=1000)
    with pytest.raises(ParameterError, match="max_num_steps"):
        rig.simulate(0.02, max_num_steps=1000.0)


def test_a_component_changed_after_runs_is_what_the_next_run_simulates():
    """Freeing a component's state after the rig has run (and kept its
    runs again) compiles the rig again: the next run is of the changed rig,
    here refused for its missing initial equation, never the old run."""
    from pdbfs.errors import ModelError
    rig = paper_rig()
    rig.simulate()
    rig.simulate()                                  # its settings and start kept on the DAE
    old = rig.compile()
    rig.hammer.free("s")
    assert rig.compile() is not old
    with pytest.raises(ModelError, match="hammer.s"):
        rig.simulate()
