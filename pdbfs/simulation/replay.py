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
from .compiled import METHOD_CODES, MSG_LEN, POINT_MSG_LEN, _stats, _text
from .kept import KeptRun
from .result import Result


@dataclass(eq=False)
class Plan:
    """What Simulator.run decided for a run of the rig's own parameters and
    start with these settings (its cache key ``key``)."""

    key: tuple
    params: list            # the DAE's parameter list the plan was made for (identity)
    grid: np.ndarray        # the simulator's kept grid: read-only
    t_addr: int             # its address (an address costs 2 us)
    p: np.ndarray
    x0: np.ndarray
    settings: dict          # rtol, atol, method, max_step, max_num_steps, backend (as in a Result)
    lib: object | None      # the rig's CompiledODE where run() answers (the compiled run and
                            # its own summary), else None: the general way


def make_plan(sim, key, kept_grid, p, x0, rtol, atol, method, max_step, max_num_steps,
              backend) -> Plan:
    """The plan of a run on ``kept_grid`` (Simulator.grid_kept's (grid, address))."""
    g, addr = kept_grid
    fast = (backend == "c" and method == "erk" and sim.nx > 0 and g[0] == 0.0
            and c_summary.usable(sim.dae, sim.compiled()))
    settings = {"rtol": rtol, "atol": atol, "method": method, "max_step": max_step,
                "max_num_steps": max_num_steps, "backend": backend}
    return Plan(key, sim.dae.params, g, addr, p.copy(), x0.copy(), settings,
                sim.compiled() if fast else None)


def run(sim, plan: Plan):
    """The plan's run: its Result."""
    lib, s = plan.lib, plan.settings
    if lib is None:
        return _general(sim, plan)
    b = lib._block()
    # this thread's arguments of the call (its buffer's addresses), by the plan's key
    # and its grid's address: a plan made again (its rig's parameter list replaced)
    # may have another grid, and the old one may be freed
    args = b.calls.get((plan.key, plan.t_addr))
    if args is None:
        if len(b.calls) > 64:
            b.calls.clear()
        a = b.addr
        args = b.calls[(plan.key, plan.t_addr)] = (
            a[0], a[1], plan.grid.size, plan.t_addr, None, float(s["rtol"]), float(s["atol"]),
            METHOD_CODES["erk"], float(s["max_step"] or 0.0), int(s["max_num_steps"]), a[2],
            a[3], MSG_LEN, a[4], a[5], a[6], POINT_MSG_LEN * 2, a[7])
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
    stats = _stats(i[1], i[3], i[5], i[2], i[6], wall)
    stats["backend"] = "c"
    return Result(sim, grid, plan.p.copy(), X, np.zeros((0, grid.size)), dict(s), stats,
                  fast_summary=fast, initial=plan.x0.copy(), states=states, own_stats=True)


def _general(sim, plan: Plan):
    s, x0 = plan.settings, plan.x0.copy()
    return sim._run(plan.grid.copy(), plan.p.copy(), x0, x0, s["rtol"], s["atol"], s["method"],
                    s["max_step"], s["max_num_steps"], s["backend"],
                    c_grid=(plan.grid, plan.t_addr))
