"""Where a CasADi run stops and restarts: the rig's time events and its
state events.

Time events are the switch times a rig declares (a valve opening or
closing, a source's step, a table's breakpoint, a prescribed motion's kink;
``dae.time_events``, functions of the parameters): the run is integrated
from switch to switch, restarting at each, so that no step can jump over
one, and each piece sees the right-hand side of its own side of the switch
up to its end (its last steps never evaluate the value after the switch).

State events are the sign changes of the rig's other event indicators
(contact onset and separation, a clamp, a slack oil column): inside each
piece they are watched on the output grid and, between output points, by
two quadratures of each indicator (the integrals of its positive and its
negative part, exactly zero while the solver never saw that sign; at the
output points inside a call they may show it up to a step early, so a
crossing is confirmed by a call that ends there), so that a contact
shorter than an output step is found too. Each is located by
integrating again from a point before it (Illinois on the indicator) until
the crossing lies within LOCATE_TO of its output interval, and the
integration restarts just past it: no step straddles a kink. The windows of
output intervals integrated at once grow from WINDOW after each start or
event. (The C drivers do the same in the compiled library,
pdbfs/native/c/shared/.) Rigs of WATCH_BELOW states or more integrate
through their state events under error control, as the compiled ones do.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

#: rigs with fewer states have their state events located (pdbfs_cvode.h's PDBFS_RESTART_BELOW)
WATCH_BELOW = 40
#: output intervals integrated at once while watching: after a start or an event
#: this many, doubled after each window without one
WINDOW = 64
#: a crossing is located to this fraction of its output interval (or a few roundoffs)
LOCATE_TO = 1e-7
#: the first state events found from as many starts are kept (Simulator.found_events)
MEMO = 512
_STATS = ("steps", "rhs_evals", "jac_evals")


def breakpoints(dae, p, t0, t1) -> np.ndarray:
    """The rig's time events strictly inside (t0, t1)."""
    b = dae.time_event_times(p)
    tol = 64 * np.finfo(float).eps * max(abs(t0), abs(t1))
    return np.unique(b[(b > t0 + tol) & (b < t1 - tol)])


def watched(dae) -> int:
    """How many state-event indicators a CasADi run locates (those after
    the time events' in ``dae.events``; none on rigs of WATCH_BELOW states
    or more)."""
    n = dae.events.numel() - dae.time_events.numel()
    return n if 0 < dae.x.numel() < WATCH_BELOW else 0


def state_indicators(dae):
    """The rig's state-event indicators (a CasADi column)."""
    return dae.events[dae.time_events.numel():]


def integrator_spec(dae, quad=None, watch=False, scaled=False) -> dict:
    """The DAE as casadi.integrator takes it: with the output ``quad``
    integrated as a quadrature, with ``watch`` the positive and negative
    parts of each state indicator after it; ``scaled``: on tau in [0, 1]
    covering [t0, t0 + h] (one object for any interval), with (t0, h,
    t_lim) after p, the right-hand side seeing time min(t, t_lim) (a piece
    that ends at a switch, t_lim just short of it, never sees past it)."""
    quads = [dae.y[dae.y_names.index(quad)]] if quad else []
    if watch:
        g = state_indicators(dae)
        quads += [ca.fmax(g, 0), ca.fmax(-g, 0)]
    spec = {"x": dae.x, "z": dae.z, "p": dae.p, "t": dae.t, "ode": dae.ode, "alg": dae.alg,
            "quad": ca.vertcat(*quads) if quads else []}
    if not scaled:
        return spec
    t0, h, tau, lim = (ca.SX.sym(n) for n in ("t0", "h", "tau", "t_lim"))
    subs = lambda e: ca.substitute(e, dae.t, ca.fmin(t0 + h * tau, lim))   # noqa: E731
    return {"x": dae.x, "z": dae.z, "p": ca.vertcat(dae.p, t0, h, lim), "t": tau,
            "ode": h * subs(dae.ode), "alg": subs(dae.alg), "quad": h * subs(ca.SX(spec["quad"]))}


def pieces(sim, grid, x0, p, rtol, atol, method, max_step, max_num_steps, force=None):
    """(X, Z, Q) on ``grid`` from x0: states, algebraics and, for the
    output ``force``, its integral from grid[0] (else None), integrated
    piece by piece between the time events, each piece with its state
    events located (a new start at each, on the time-scaled integrator)."""
    grid = np.asarray(grid, float)
    s = (rtol, atol, method, max_step, max_num_steps)
    b = breakpoints(sim.dae, p, grid[0], grid[-1])
    tol = 64 * np.finfo(float).eps * max(abs(grid[0]), abs(grid[-1]))
    k = np.clip(np.searchsorted(grid, b), 1, grid.size - 1)   # snap onto close grid points
    near = np.where(np.abs(grid[k] - b) <= np.abs(grid[k - 1] - b), grid[k], grid[k - 1])
    b = np.unique(np.where(np.abs(near - b) <= tol, near, b))
    edges = np.concatenate([[grid[0]], b, [grid[-1]]])
    nx, nz = sim.dae.x.numel(), sim.dae.z.numel()
    X, Z = np.zeros((nx, grid.size)), np.zeros((nz, grid.size))
    Q = np.zeros(grid.size) if force else None
    X[:, 0] = x0
    x, total, impulse = np.asarray(x0, float), {"root_events": int(b.size)}, 0.0
    for i, (a, c) in enumerate(zip(edges[:-1], edges[1:])):
        sub = np.concatenate([[a], grid[(grid > a) & (grid < c)], [c]])
        # a piece that ends at a switch sees time just short of it to the end
        t_lim = np.nextafter(c, -np.inf) if i < edges.size - 2 else np.inf
        Xs, Zs, Qs = _piece(sim, sub, x, p, s, force, t_lim, total)
        at = np.searchsorted(grid, sub)
        on = (at < grid.size) & (grid[np.minimum(at, grid.size - 1)] == sub)
        if i > 0:
            on[0] = False          # the switch point itself: the piece before wrote it
        X[:, at[on]], Z[:, at[on]] = Xs[:, on], Zs[:, on]
        if force:
            Q[at[on]] = impulse + Qs[on]
            impulse += float(Qs[-1])
        if i == 0:
            Z[:, 0] = Zs[:, 0]
        x = Xs[:, -1]
    sim._last_stats = dict(sim._last_stats, **total)
    return X, Z, Q


def _piece(sim, sub, x, p, s, force, t_lim, total):
    """(X, Z, Q) on ``sub`` from x at sub[0] (Q: the force's integral from
    sub[0], or None), the state events inside located; the solver's
    statistics summed into ``total``."""
    ne = watched(sim.dae)
    if not ne:
        X, Z, Qr = _call(sim, sub, x, p, s, force, t_lim, total)
        return X, Z, (Qr[0] if force else None)
    n, nx, nz = sub.size, sim.dae.x.numel(), sim.dae.z.numel()
    X, Z, Q = np.zeros((nx, n)), np.zeros((nz, n)), np.zeros(n)
    X[:, 0] = x
    t, k, w, q0, skip = float(sub[0]), 0, WINDOW, 0.0, None
    if nz:
        Z[:, 0] = _z_at(sim, t, x, p)
    while k < n - 1:
        key = (t, x.tobytes(), p.tobytes(), s, t_lim, bool(force))
        known = sim.found_events.get(key)
        if known is not None and known[0] <= sub[k + 1]:    # found from here before
            t, x, q_r, skip = known[0], known[1], known[2], known[3]
            q0 += q_r
            total["root_events"] = total.get("root_events", 0) + 1
            w = WINDOW
            if t >= sub[k + 1]:
                k += 1
                X[:, k], Z[:, k], Q[k] = x, _z_at(sim, t, x, p), q0
            continue
        # windows of a few shapes, cached: one interval from a point between output points
        j1 = k + (1 if t > sub[k] else _pow2_below(min(w, n - 1 - k)))
        local = np.concatenate([[t], sub[k + 1:j1 + 1]])
        Xw, Zw, Qw = _call(sim, local, x, p, s, force, t_lim, total, watch=True)
        hit = _first_crossing(sim, local, Xw, Zw, Qw, p, ne, skip)
        last = j1 - k if hit is None else hit[0]       # the local points before the crossing
        X[:, k + 1:k + last + 1], Z[:, k + 1:k + last + 1] = Xw[:, 1:last + 1], Zw[:, 1:last + 1]
        if force:
            Q[k + 1:k + last + 1] = q0 + Qw[0, 1:last + 1]
        if hit is None:
            x, t, k, w, skip = Xw[:, -1], float(local[-1]), j1, 2 * w, None
            q0 += float(Qw[0, -1]) if force else 0.0
            continue
        j, i, G = hit
        q_start = q0
        found = _locate(sim, local[j], local[j + 1], Xw[:, j], G[:, j], G[:, j + 1], i, p, s,
                        force, t_lim, total, ne)
        t_r, x_r, q_r = found[:3]
        q0 += (float(Qw[0, j]) if force else 0.0) + q_r
        k, x, t, w, skip = k + j, x_r, t_r, WINDOW, None
        if found[3] is not None:          # an event: restarted just past it
            total["root_events"] = total.get("root_events", 0) + 1
            i = found[3]
            # the indicator restarted at is at its root there: its side after it
            G = sim.events_on(np.array([t_r]), x_r[:, None], _z_at(sim, t_r, x_r, p)[:, None], p)
            skip = (i, t_r, np.sign(G[-ne + i, 0]))
            if len(sim.found_events) >= MEMO:
                sim.found_events.clear()
            # the first event after this window's start (values between output points
            # integrate from the same start again and again)
            sim.found_events[key] = (t_r, x_r, q0 - q_start, skip)
        if t_r >= sub[k + 1]:             # at the next output point
            k += 1
            X[:, k], Z[:, k], Q[k] = x_r, _z_at(sim, t_r, x_r, p), q0
    return X, Z, (Q if force else None)


def _pow2_below(n: int) -> int:
    """The largest power of two not above n (n >= 1)."""
    return 1 << (int(n).bit_length() - 1)


def _first_crossing(sim, local, X, Z, Qw, p, ne, skip):
    """(j, i, G): the first interval [local[j], local[j+1]] in which an
    indicator i was seen on both sides of zero (at its ends, or by its
    quadratures), and the indicators on ``local``; None where none was. ``skip`` (i, t, side): indicator i, restarted at
    its root t, is not looked at in the interval that begins there unless
    it ends that interval off ``side`` (back across already)."""
    G = sim.events_on(local, X, Z, p)[-ne:]
    W = Qw[-2 * ne:]
    up, down = np.diff(W[:ne], axis=1) > 0, np.diff(W[ne:], axis=1) > 0
    pos = (G[:, :-1] > 0) | (G[:, 1:] > 0) | up
    neg = (G[:, :-1] < 0) | (G[:, 1:] < 0) | down
    both = pos & neg
    if skip is not None and local[0] == skip[1]:
        end = np.sign(G[skip[0], 1])
        if skip[2] == 0 or end in (skip[2], 0):
            both[skip[0], 0] = False
    hits = np.flatnonzero(both.any(axis=0))
    if not hits.size:
        return None
    j = int(hits[0])
    return j, int(np.flatnonzero(both[:, j])[0]), G


def _locate(sim, ta, tb, xa, ga, gb, i, p, s, force, t_lim, total, ne):
    """The first crossing in [ta, tb] from xa at ta (indicators ga and gb
    at its ends, i the one seen crossing). One call of the integrator from
    a point before the crossing shows exactly whether its interval holds one
    (the indicators and quadratures at its end; those at points inside may
    show it up to a step early, since CVODES steps past an output time and
    interpolates back): the bracket is narrowed by such calls from its left
    end, at the secant root of the crossing indicator where its ends differ
    in sign (Illinois), else at its middle, until it is LOCATE_TO of the
    interval wide. Returns (t, x, q, i): the bracket's right end (just past
    the root) and the state there, the force's integral from ta to t, and
    the indicator; i None and t = tb where nothing crosses."""
    eps = np.finfo(float).eps
    tol = max(LOCATE_TO * (tb - ta), 8 * eps * max(abs(ta), abs(tb)))
    a, b, x, q, found, side = float(ta), float(tb), np.asarray(xa, float), 0.0, None, 0
    while True:
        if b - a <= tol and found is not None:
            return found + (i,)
        fa, fb = ga[i], gb[i]
        if abs(side) > 1:                 # the same end moved twice: halve the other's weight
            fa, fb = (fa, fb / 2 ** (abs(side) - 1)) if side > 0 else (fa / 2 ** (abs(side) - 1), fb)
        c = a + (b - a) * fa / (fa - fb) if fa * fb < 0 else 0.5 * (a + b)
        c = min(max(c, a + 0.5 * tol), b - 0.5 * tol)
        if found is None and (fa * fb >= 0 or b - a <= tol) or not a < c < b:
            c = b                         # seen by a quadrature only: confirmed first
        local = np.array([a, c])
        Xl, Zl, Ql = _call(sim, local, x, p, s, force, t_lim, total, watch=True)
        hit = _first_crossing(sim, local, Xl, Zl, Ql, p, ne, None)
        qc = q + (float(Ql[0, -1]) if force else 0.0)
        if hit is None:                   # nothing up to c: the bracket begins there
            if c == b:
                return b, Xl[:, -1], qc, None
            ga = sim.events_on(local[1:], Xl[:, 1:], Zl[:, 1:], p)[-ne:, 0]
            a, x, q = c, Xl[:, -1], qc
            side = side + 1 if side > 0 else 1
        else:
            b, found, gb, i = c, (c, Xl[:, -1], qc), hit[2][:, 1], hit[1]
            side = side - 1 if side < 0 else -1


def _z_at(sim, t, x, p):
    """The algebraic variables at (t, x) (none on an ODE rig)."""
    return sim.z_guess(p) if sim.dae.is_ode else sim.consistent_start(t, x, p)[0]


def _call(sim, local, x, p, s, force, t_lim, total, watch=False):
    """One call of the time-scaled integrator over ``local`` from x
    (Simulator.scaled_run), its statistics summed into ``total``."""
    out = sim.scaled_run(local, x, p, s, force=force, watch=watch, t_lim=t_lim)
    for key in _STATS:
        total[key] = total.get(key, 0) + sim._last_stats.get(key, 0)
    return out
