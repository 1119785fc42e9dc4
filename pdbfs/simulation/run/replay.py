"""A run with everything of a run before: the rig's own parameters and start,
the same settings (``Simulator.run``'s plan). Nothing is decided or checked
again: the compiled call, and its Result. ``rig.simulate()`` with no options
finds its plan itself (``own``: kept in the rig's state by t_end,
one_run.simulate_own), without Simulator.run's arguments and key. Runs that give new parameters have plans
of their own settings: Simulator.run checks the parameters and decides their
start and method, and where that is the plan's method, the plan's call is
made with them (``run(sim, plan, p, x0)``).

Why a path of its own: Python's share of a run is paid again in full after
other work. Measured on this project's machine, the first Python after 5 ms
of other Python ran 2-4x slower than warm (a chain of 120 calls: 15 -> 41
us), while compiled code lost a tenth; so between other tools a compiled run
took 0.2 ms of C and up to 0.1 ms of Python. Here the Python is a few
frames (C reads the plan's own parameters and start, and its answers come
back in one unpacking); anything but a run that went well and whose summary
the driver gave (a failure, a pulse cut off at t_end, ...) goes the general
way, ``Simulator._run``, and is answered (and explained) there.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..results import c_summary
from ..results.result import Result
from ..setup import memory
from .compiled import INFO_N, METHOD_CODES, MSG_LEN, POINT_MSG_LEN, SUMMARY_KEYS, _stats, _text
from .kept import KeptRun

# where Block.unpack's answers have the summary's values and its code
_VALUES = INFO_N
_CODE = INFO_N + len(SUMMARY_KEYS)


@dataclass(eq=False)
class Plan:
    """What Simulator.run decided for a run of the rig's own parameters and
    start with these settings (its cache key ``key``)."""

    key: tuple
    params: list            # the DAE's parameter list the plan was made for (identity)
    grid: np.ndarray        # the simulator's kept grid: read-only
    t_addr: int             # its address (an address costs 2 us)
    p: np.ndarray           # never written: C reads it where it is
    x0: np.ndarray          # the same
    settings: dict          # rtol, atol, method, max_step, max_num_steps, backend (as in a Result)
    lib: object | None      # the rig's CompiledODE where run() answers (the compiled run and
                            # its own summary), else None: the general way
    Z: np.ndarray           # a Result's algebraic outputs: none (no element: shared)
    #: each thread's call: its Block -> (the arguments with the plan's p and x0, with the
    #: Block's); the plan holds every array whose address is there
    calls: dict = field(default_factory=dict)


def key(t_end, n_out, rtol, atol, method, max_step, max_num_steps, backend,
        new_params=False) -> tuple:
    """The cache key of Simulator.run's plan for these settings (their types
    too: 1 and 1.0 are not the same request), for the rig's own parameters or
    (``new_params``) for runs that give theirs."""
    return ("plan", type(t_end), t_end, type(n_out), n_out, type(rtol), rtol, type(atol), atol,
            method, type(max_step), max_step, type(max_num_steps), max_num_steps, backend,
            new_params)


def make_plan(sim, key, kept_grid, p, x0, rtol, atol, method, max_step, max_num_steps,
              backend) -> Plan:
    """The plan of a run on ``kept_grid`` (Simulator.grid_kept's (grid, address))."""
    g, addr = kept_grid
    fast = (backend == "c" and method == "erk" and sim.nx > 0 and g[0] == 0.0
            and c_summary.usable(sim.dae, sim.compiled()))
    settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                "max_num_steps": max_num_steps, "backend": backend}
    p, x0 = p.copy(), x0.copy()
    p.flags.writeable = x0.flags.writeable = False     # C reads them where they are
    return Plan(key, sim.dae.params, g, addr, p, x0, settings,
                sim.compiled() if fast else None, np.zeros((0, g.size)))


def own(sim, t_end):
    """``sim.run(t_end)`` (Rig.simulate() with no options), its plan kept in
    the rig's state by ``t_end`` for the next such call: one_run.simulate_own
    replays it without Simulator.run's arguments and checks."""
    r = sim.run(t_end)
    d = type(sim).run.__kwdefaults__         # run's defaults: the key run() made
    plan = sim._cache.get(key(t_end, type(sim).run.__defaults__[1], d["rtol"], d["atol"],
                              d["method"], d["max_step"], d["max_num_steps"], d["backend"],
                              False)) \
        if type(t_end) is float else None
    if plan is not None:
        plans = sim.state.own_plans
        if len(plans) > 16:
            plans.clear()
        plans[t_end] = (sim, plan)
    return r


def run(sim, plan: Plan, p=None, x0=None):
    """The plan's run: its Result; with ``p`` and ``x0`` (new parameters, checked,
    and their start, Simulator.run), the plan's call with those."""
    lib = plan.lib
    if lib is None:
        return _general(sim, plan)
    b = lib._blocks.__dict__.get("block") or lib._block()
    call = plan.calls.get(b)
    if call is None:
        call = _call(plan, b)
    args, args_b = call
    if p is None:
        shared = (plan.p, plan.x0)
    else:                         # the same call, p and x0 from the thread's Block
        b.p[:] = p
        b.x0[:] = x0
        args, shared = args_b, (p, x0)
    wall = time.perf_counter()
    code = lib._run_summary(*args)
    wall = time.perf_counter() - wall
    a = b.unpack(b.bytes)      # info[0..6], the summary's values, its code, the note's start, handle
    handle = a[-1]
    if code or not handle:
        if handle:
            lib._release(handle)
        memory.interrupted()                          # a Ctrl-C the record's probe kept
        return _general(sim, plan, *shared)           # to say what went wrong
    kept = KeptRun(lib, handle, plan.grid, int(a[1]))
    if memory.kept_interrupt:        # raised with the record released (KeptRun)
        memory.interrupted()
    fast = (list(a[_VALUES:_CODE]), a[_CODE], _text(b.note, strip=False) if a[_CODE + 1] else "")
    X, states = sim._kept_or_states(kept, plan.grid)
    stats = _stats(a[1], a[3], a[5], a[2], a[6], wall)
    stats["backend"] = "c"
    # no numpy call here: after other work numpy's first costs 10-20 us (module doc); the
    # Result copies the plan's t and p when they are first read, its start is only read
    return Result(sim, plan.grid, shared[0], X, plan.Z, dict(plan.settings), stats,
                  fast_summary=fast, initial=shared[1], states=states, own_stats=True,
                  shared=True)


def _call(plan: Plan, b) -> tuple:
    """This thread's arguments of the plan's call (``b``'s addresses): with the
    plan's p and x0, and with the Block's."""
    if len(plan.calls) > 64:                     # threads come and go: their Blocks with them
        plan.calls.clear()
    s, a = plan.settings, b.addr
    args = (plan.p.ctypes.data, plan.x0.ctypes.data, plan.grid.size, plan.t_addr, None,
            float(s["rtol"]), float(s["atol"]), METHOD_CODES["erk"], float(s["max_step"] or 0.0),
            int(s["max_num_steps"]), a[2], a[3], MSG_LEN, a[4], a[5], a[6], POINT_MSG_LEN * 2,
            a[7])
    call = plan.calls[b] = (args, (a[0], a[1]) + args[2:])
    return call


def _general(sim, plan: Plan, p=None, x0=None):
    s = plan.settings
    p = (plan.p if p is None else p).copy()
    x0 = (plan.x0 if x0 is None else x0).copy()
    return sim._run(plan.grid.copy(), p, x0, x0, s["rtol"], s["atol"], s["method"],
                    s["max_step"], s["max_num_steps"], s["backend"],
                    c_grid=(plan.grid, plan.t_addr))
