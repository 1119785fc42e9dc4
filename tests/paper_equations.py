"""The paper's equations of motion (PHYSICS.md, eq. 9) written by hand with
numpy: the independent reference the tests and the benchmark compare
pdbfs against. Not used by pdbfs itself."""
import numpy as np
from scipy.integrate import solve_ivp

TABLE1 = dict(m1=2948.4, m2=241.7, m3=500.0, k1=5.958e10, n=1.5, D=1.595e6, k2=2.228e8,
              k3=2.5e10, c2=2.556e4, A=2.270e-2, v0=2.73)


def make_rhs(m1, m2, m3, k1, n, D, k2, k3, c2, A, v0, n2=1.0):
    """Right-hand side in plain numpy, the way one writes it by hand."""
    M = np.array([m1, m2, m3])

    def forces(y):
        x, v = y[0::2], y[1::2]
        d = x[0] - x[1]
        dn = np.maximum(d, 0.0) ** n
        fc = max(k1 * dn + D * dn * (v[0] - v[1]), 0.0)
        fo = k2 * np.maximum(x[1] - x[2], 0.0) ** n2
        return fc, fo

    def rhs(t, y):
        x, v = y[0::2], y[1::2]
        fc, fo = forces(y)
        f = np.array([-fc, fc - fo - c2 * v[1], fo - k3 * x[2]])
        out = np.empty(6)
        out[0::2] = v
        out[1::2] = f / M
        return out

    # event functions: contact onset/separation, clamp of the damped force, oil slack
    def ev_d(t, y):
        return y[0] - y[2]

    def ev_clamp(t, y):
        return k1 + D * (y[1] - y[3])

    def ev_oil(t, y):
        return y[2] - y[4]

    return rhs, forces, [ev_d, ev_clamp, ev_oil]


def pressure(sol_y, p):
    do = sol_y[2] - sol_y[4]
    return np.where(do > 0, p["k2"] * np.clip(do, 0, None) ** p.get("n2", 1.0), 0.0) / p["A"]


def reference(t_out, rtol=1e-12, atol=1e-15, **over):
    """A tight solution restarted at every non-smooth point (event location),
    so that no step straddles a kink. Returns states at t_out (6 x N)."""
    p = dict(TABLE1, **over)
    rhs, _, events = make_rhs(**p)
    for e in events:
        e.terminal = True
    t0, y0 = 0.0, np.array([0, p["v0"], 0, 0, 0, 0], float)
    out = np.empty((6, len(t_out)))
    t_end = t_out[-1]
    while True:
        mask = (t_out >= t0) & (t_out <= t_end)
        sol = solve_ivp(rhs, (t0, t_end), y0, method="DOP853", rtol=rtol, atol=atol,
                        events=events, dense_output=True)
        stop = sol.t[-1]
        take = mask & (t_out <= stop)
        if take.any():            # (a short segment between two events may hold no output time)
            out[:, take] = sol.sol(t_out[take])
        if sol.status != 1 or stop >= t_end:
            break
        # step just past the event so it does not trigger again at once
        t0 = stop + 1e-12
        y0 = sol.sol(t0)
    return out, p



def blow_reference(t_end=0.02, rtol=1e-12, **over):
    """The figures of the paper rig's blow, every one located as an event of
    a tight solution (the integration restarted at each, so no step
    straddles a kink; atol 1e-30: signals of any size). Returns a dict:

    restitution   Guo & Batzer's ratio as pdbfs defines it with a striker
                  (summary.py): the contact force's impulse (integrated as a
                  seventh state) after the hammer stops (v1 turns from down
                  to up) up to t_end, over its impulse before
    first_contact the first contact's duration, s
    contacts      the number of contacts
    peak_pressure the highest oil pressure, Pa (where v2 - v3 turns from up to down)
    time_of_peak  s
    """
    p = dict(TABLE1, **over)
    rhs6, forces, kinks = make_rhs(**p)

    def rhs(t, y):
        return np.append(rhs6(t, y[:6]), forces(y[:6])[0])
    events = [lambda t, y, e=e: e(t, y[:6]) for e in kinks] + \
        [lambda t, y: y[1], lambda t, y: y[3] - y[5]]
    stop, turn = len(events) - 2, len(events) - 1
    t, y = 0.0, np.array([0, p["v0"], 0, 0, 0, 0, 0.0])
    # each event looks for the crossing away from its side; those at zero at the start
    # (the indentation, the oil) are about to grow
    side = [1.0 if e(t, y) >= 0 else -1.0 for e in events]
    q_stop, touches, peak = None, [], (0.0, 0.0)
    while t < t_end:
        for e, sd in zip(events, side):
            e.terminal, e.direction = True, -sd
        sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=rtol, atol=1e-30,
                        events=events)
        if sol.status != 1:
            y = sol.y[:, -1]
            break
        i = min((k for k in range(len(events)) if len(sol.t_events[k])),
                key=lambda k: sol.t_events[k][0])
        t, y = sol.t_events[i][0], sol.y_events[i][0]
        side[i] = -side[i]
        if i == stop and q_stop is None and side[i] < 0:
            q_stop = y[6]                      # the hammer stops: the split
        if i == turn and side[i] < 0:          # the oil's compression at a maximum
            level = p["k2"] * max(y[2] - y[4], 0.0) ** p.get("n2", 1.0) / p["A"]
            peak = max(peak, (level, t))
        if i == 0:
            touches.append(t)                  # a separation, or a contact's onset
    return {"restitution": (y[6] - q_stop) / q_stop,
            "first_contact": touches[0] if touches else None,   # the first began at t = 0
            "contacts": (len(touches) + 1) // 2,
            "peak_pressure": peak[0], "time_of_peak": peak[1]}
