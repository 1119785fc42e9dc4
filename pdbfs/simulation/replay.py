"""A run with everything of a run before: the rig's own parameters and start,
the same settings (``Simulator.run``'s plan). Nothing is decided or checked
again: the compiled call, and its Result.

Why a path of its own: Python's share of a run is paid again in full after
other work. Measured on this project's machine, the first Python after 5 ms
of other Python ran 2-4x slower than warm (a chain of 120 calls: 15 -> 41
us), while compiled code lost a tenth; so between other tools a compiled run
took 0.2 ms of C and up to 0.1 ms of Python. Here the Python is a few
frames; anything but a run that went well and whose summary the driver gave
(a failure, a pulse cut off at t_end, ...) goes the general way,
``Simulator._run``, and is answered (and explained) there.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from . import c_summary
from .compiled import METHOD_CODES, MSG_LEN, POINT_MSG_LEN, _text, solver_name
from .kept import KeptRun
from .result import Result


@dataclass(eq=False)
class Plan:
    """What Simulator.run decided for a run of the rig's own parameters and
    start with these settings (its cache key ``key``)."""

    key: tuple
    params: list            # the DAE's parameter list the plan was made for (identity)
    grid: np.ndarray        # read-only
    t_addr: int             # the grid's address (an address costs 2 us)
    p: np.ndarray
    x0: np.ndarray
    rtol: float
    atol: float
    method: str
    max_step: float | None
    max_num_steps: int
    backend: str
    fast: bool = False      # the compiled run and its own summary (run())
    lib: object | None = None      # with fast: the rig's CompiledODE
    settings: dict | None = None   # as a Result has them (a copy for each)


def make_plan(sim, key, grid, p, x0, rtol, atol, method, max_step, max_num_steps,
              backend) -> Plan:
    g = grid.copy()
    g.flags.writeable = False
    plan = Plan(key, sim.dae.params, g, g.ctypes.data, p.copy(), x0.copy(), rtol, atol, method,
                max_step, max_num_steps, backend)
    plan.fast = (backend == "c" and method == "erk" and sim.nx > 0 and g[0] == 0.0
                 and c_summary.usable(sim.dae, sim.compiled()))
    plan.lib = sim.compiled() if plan.fast else None
    plan.settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                     "max_num_steps": max_num_steps, "backend": backend}
    return plan


def run(sim, plan: Plan):
    """The plan's run: its Result."""
    if not plan.fast:
        return _general(sim, plan)
    lib = plan.lib
    b = lib._block()
    # this thread's arguments of the call (its buffer's addresses), by the plan's key
    # and its grid's address: a plan made again (its rig's parameter list replaced)
    # has a grid of its own, and the old one may be freed
    args = b.calls.get((plan.key, plan.t_addr))
    if args is None:
        if len(b.calls) > 64:
            b.calls.clear()
        a = b.addr
        args = b.calls[(plan.key, plan.t_addr)] = (
            a[0], a[1], plan.grid.size, plan.t_addr, None, float(plan.rtol), float(plan.atol),
            METHOD_CODES["erk"], float(plan.max_step or 0.0), int(plan.max_num_steps), a[2], a[3],
            MSG_LEN, a[4], a[5], a[6], POINT_MSG_LEN * 2, a[7])
    b.p[:] = plan.p
    b.x0[:] = plan.x0
    wall = time.perf_counter()
    code = lib._run_summary(*args)
    wall = time.perf_counter() - wall
    handle = int(b.handle[0])
    if code or not handle:
        if handle:
            lib._release(handle)
        return _general(sim, plan)                    # to say what went wrong
    i = b.info.tolist()
    kept = KeptRun(lib, handle, plan.grid, int(i[1]))
    fast = (b.out.tolist(), int(b.code[0]), _text(b.note, strip=False))
    grid = plan.grid.copy()
    X, states = sim._kept_or_states(kept, grid)
    stats = {"steps": int(i[1]), "rhs_evals": int(i[3]), "jac_evals": int(i[5]),
             "root_events": int(i[2]), "method": solver_name(i[6])}
    sim._last_stats = stats
    stats = dict(stats, wall_time=wall, backend="c")
    return Result(sim, grid, plan.p.copy(), X, np.zeros((0, grid.size)), dict(plan.settings),
                  stats, fast_summary=fast, initial=plan.x0.copy(), states=states, own_stats=True)


def _general(sim, plan: Plan):
    x0 = plan.x0.copy()
    return sim._run(plan.grid.copy(), plan.p.copy(), x0, x0, plan.rtol, plan.atol, plan.method,
                    plan.max_step, plan.max_num_steps, plan.backend,
                    c_grid=(plan.grid, plan.t_addr))
