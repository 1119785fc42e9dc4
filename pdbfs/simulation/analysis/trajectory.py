"""A rig's simulation as a CasADi Function of its parameters.

    f = trajectory_function(paper_rig(), ["oil.pressure"], inputs=["oil.k", "seal.c"])
    Y = f([2.228e8, 2.556e4])                        # 1 x n_out
    J = casadi.Function("J", [p := casadi.MX.sym("p", 2)], [casadi.jacobian(f(p), p)])

The Function wraps the same cached CVODES/IDAS integrator as ``simulate``;
CasADi differentiates it (forward sensitivities of SUNDIALS) and evaluates
it on many points (``f.map``): the ground for calibration and inverse
design on the same DAE.
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np

from pdbfs.errors import ParameterError
from ..run.simulator import MAX_NUM_STEPS, Simulator
from ..setup.initialize import refuse_solved_start
from ..setup.settings import default_atol, name_list
from ..setup.time_events import breakpoints

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from pdbfs.modelling import DAE, Component


def trajectory_function(model: Component | DAE, outputs: str | Sequence[str], t_end: float = 0.02,
                        n_out: int = 2001, *, t_out: ArrayLike | None = None,
                        inputs: str | Sequence[str] | None = None,
                        params: Mapping[str, float] | None = None, rtol: float = 1e-8,
                        atol: float | None = None, method: str = "auto",
                        max_step: float | None = None) -> ca.Function:
    """A rig's simulation as a CasADi Function of its parameters, ``p -> y``,
    which CasADi differentiates (forward sensitivities of SUNDIALS) and maps
    over many points (``f.map``).

    Parameters
    ----------
    model : Component or DAE
        The rig, or its compiled DAE.
    outputs : str or sequence of str
        The variables (dotted names): the rows of ``y``, on the output grid.
    t_end : float
        End time of the run, s.
    n_out : int
        Number of output points, evenly spaced on [0, t_end]: the columns of ``y``.
    t_out : array_like, optional
        Output times, s, increasing from 0 (overrides ``t_end`` and ``n_out``).
    inputs : str or sequence of str, optional
        The parameters that are the Function's input ``p``, in that order
        (default: every free parameter, in the DAE's order).
    params : mapping of str to float, optional
        Values, SI units, of parameters that are not among ``inputs``
        (the others keep their defaults).
    rtol, atol : float
        Tolerances of the integrator (``atol`` None: as in ``simulate``).
    method : {"auto", "adams", "bdf"}
        The integration method, as in ``simulate`` (through CasADi).
    max_step : float, optional
        Largest internal step, s.

    Returns
    -------
    casadi.Function
        ``y = f(p)``: one row per output, one column per output time.
        Called with numbers, it checks them as ``simulate`` does (one value
        per input, each within its parameter's range).

    Raises
    ------
    pdbfs.ParameterError
        For an output or parameter the rig does not have, before any work.

    Examples
    --------
    >>> from pdbfs import trajectory_function
    >>> from pdbfs.models import paper_rig
    >>> f = trajectory_function(paper_rig(), "oil.pressure", 0.01, 11, inputs=["oil.k"])
    >>> y = f(2.228e8)
    >>> y.shape, f"{float(y[0, 5]) / 1e6:.3g} MPa at 5 ms"
    ((1, 11), '82.2 MPa at 5 ms')
    """
    sim = Simulator.of(model)
    dae = sim.dae
    grid = sim.grid(t_end, n_out, t_out)
    index = {n: i for i, n in enumerate(dae.y_names)}
    outputs = name_list(outputs, "outputs", distinct=False)
    missing = [n for n in outputs if n not in index]
    if missing or not outputs:
        raise ParameterError(f"trajectory_function: unknown output(s) {', '.join(missing)} of "
                             f"rig {dae.name}" if missing else "trajectory_function: no outputs")
    inputs = list(dae.p_names) if inputs is None else name_list(inputs, "inputs", "'oil.k'")
    p_index = {n: i for i, n in enumerate(dae.p_names)}
    unknown = [n for n in inputs if n not in p_index]
    if unknown:
        sim.param_vector({unknown[0]: 0.0})   # raises the usual error, with suggestions
    p0 = sim.param_vector(params)
    refuse_solved_start(dae, "trajectory_function")

    u = ca.MX.sym("p", len(inputs))
    p = ca.MX(p0)                         # dense MX column of the full parameter vector
    for k, name in enumerate(inputs):
        p[p_index[name]] = u[k]
    x0 = dae.function("start")(p)
    method = sim.resolve_method(method, p0, dae.function("start")(p0).full().ravel(),
                                grid[-1] - grid[0])
    X, Z = symbolic_states(sim, grid, x0, p, p0, rtol, default_atol(rtol, atol), method,
                           max_step, inputs)
    n = len(grid)
    rows = ca.vertcat(*[dae.y[index[name]] for name in outputs])
    out = ca.Function("out", [dae.t, dae.x, dae.z, dae.p], [rows]).map(n)
    y = out(ca.DM(np.asarray(grid).reshape(1, -1)), X, Z, ca.repmat(p, 1, n))
    return Trajectory(sim, inputs, p0, [u], [y])


class Trajectory(ca.Function):
    """The trajectory Function; called with numbers, it checks them as
    simulate does (one value per input, each within its parameter's range)."""

    def __init__(self, sim, inputs, p0, ins, outs):
        super().__init__("trajectory", ins, outs, ["p"], ["y"])
        self._check = (sim, list(inputs), np.asarray(p0, float))

    def __call__(self, *args, **kwargs):
        values = args[0] if args else kwargs.get("p")
        if values is not None and not isinstance(values, (ca.MX, ca.SX)):
            sim, inputs, p0 = self._check
            v = np.asarray(values.full() if isinstance(values, ca.DM) else values, dtype=float)
            if v.size != len(inputs):
                raise ParameterError(f"trajectory: {v.size} value(s) for {len(inputs)} input(s) "
                                     f"({', '.join(inputs)}); give one value each")
            params = dict(zip(sim.dae.p_names, p0))
            params.update(zip(inputs, v.ravel()))
            sim.param_vector(params)       # ranges and consistency, as simulate checks them
        return super().__call__(*args, **kwargs)


def moving_time_events(dae, inputs) -> np.ndarray:
    """Which of the rig's time events depend on the parameters ``inputs``."""
    cols = [dae.p_names.index(n) for n in inputs]
    return np.array([any(ca.depends_on(dae.time_events[k], dae.p[i]) for i in cols)
                     for k in range(dae.time_events.numel())], dtype=bool)


def symbolic_states(sim, grid, x0, p, p0, rtol, atol, method, max_step, inputs=()):
    """States and algebraics (MX, one column per grid point) from x0 at
    grid[0], as functions of the MX parameters p: one integrator call per
    piece between the rig's time events (at p0), each restarted there.
    Switch times that move with the ``inputs`` cannot split a fixed grid:
    they are integrated through, in steps no longer than half the shortest
    interval between switch times (at p0), so that every interval between
    two switches holds steps and none is stepped over whole."""
    dae = sim.dae
    grid = np.asarray(grid, float)
    b = breakpoints(dae, p0, grid[0], grid[-1])
    moving = moving_time_events(dae, inputs)
    if moving.any():
        times = np.array(ca.Function("te", [dae.p], [dae.time_events])(p0)).ravel()
        still = times[~moving]
        b = np.unique(still[(still > grid[0]) & (still < grid[-1])])
        gaps = np.diff(np.unique(np.concatenate([times, grid[[0, -1]]])))
        h = float(np.min(gaps[gaps > 0])) / 2
        max_step = h if max_step is None else min(max_step, h)
    z0 = sim.z_guess(p0)
    if not b.size:
        F = sim.integrator(grid, rtol, atol, method, max_step, max_num_steps=MAX_NUM_STEPS)
        r = F(x0=x0, p=p, z0=z0)
        return r["xf"], r["zf"]
    edges = np.concatenate([[grid[0]], b, [grid[-1]]])
    Xs, Zs, x = [], [], x0
    for i, (a, c) in enumerate(zip(edges[:-1], edges[1:])):
        inner = grid[(grid > a) & (grid < c)]
        sub = np.concatenate([[a], inner, [c]])
        F = sim.integrator((sub - a) / (c - a), rtol, atol, method, max_step, scaled=True,
                           max_num_steps=MAX_NUM_STEPS)
        r = F(x0=x, p=ca.vertcat(p, a, c - a, np.nextafter(c, -np.inf) if c < grid[-1] else np.inf),
              z0=z0)
        keep = [j for j in range(sub.size) if (j > 0 or i == 0) and (
            0 < j < sub.size - 1 or sub[j] in grid)]
        Xs.append(r["xf"][:, keep])
        Zs.append(ca.reshape(r["zf"], dae.z.numel(), sub.size)[:, keep] if dae.z.numel() else
                  ca.MX(0, len(keep)))
        x = r["xf"][:, -1]
    return ca.horzcat(*Xs), ca.horzcat(*Zs)
