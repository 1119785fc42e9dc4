"""The states of a run with inputs as CasADi expressions of chosen
parameters (trajectory.symbolic_states' counterpart, for calibration and
design with a measured command): one piece per segment of the inputs,
each integrated by symbolic_states with the segment's input values and
slopes as numbers in p (the rig's own time events split it further), and
every output point evaluated with its own inputs."""
from __future__ import annotations

import casadi as ca
import numpy as np

from .trajectory import symbolic_states


def driven_states(sim, grid, x0, p, p0, drive, rtol, atol, method, max_step, targets=()):
    """(X, Z) (MX, one column per grid point) from x0 at grid[0], as functions
    of the MX parameters ``p`` (whose input rows are replaced per segment by
    the Drive's numbers)."""
    grid = np.asarray(grid, float)
    u0 = drive.u0
    Xs, Zs, x = [], [], x0
    for i, (a, c, sub) in enumerate(drive.pieces(grid)):
        q0 = drive.p_at(p0, a, c)
        q = ca.vertcat(p[:u0], ca.DM(q0[u0:]))
        X, Z = symbolic_states(sim, sub, x, q, q0, rtol, atol, method, max_step, targets)
        on = np.isin(sub, grid)
        cols = [j for j in range(sub.size) if on[j] and (j > 0 or i == 0)]
        if i > 0 and on[0]:          # a breakpoint on the grid: the later segment's z (right side)
            cols = [0] + cols
            Xs[-1], Zs[-1] = Xs[-1][:, :-1], Zs[-1][:, :-1]
        Xs.append(X[:, cols])
        Zs.append(Z[:, cols] if Z.shape[0] else ca.MX(0, len(cols)))
        x = X[:, -1]
    return ca.horzcat(*Xs), ca.horzcat(*Zs)


def driven_columns(p, drive, grid):
    """p for every grid point (MX, one column each): the parameters of ``p``
    repeated, the inputs of each point (Drive.P_on) as numbers."""
    n = len(grid)
    P_in = drive.P_on(np.zeros(drive.t_ref + 1), grid)[drive.u0:]
    return ca.vertcat(ca.repmat(p[:drive.u0], 1, n), ca.DM(P_in))
