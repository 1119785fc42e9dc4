"""Signals of time that the rig differentiates must not jump where they
switch.

Alias elimination and index reduction differentiate an expression of time
where the rig needs its rate: a SignalPosition driven by a source block
(the damper needs the prescribed position's velocity), a Position's
function. CasADi's derivative of a switch (``if_else(time >= t0, h, 0)``)
is 0 on both sides, so a jump there would be taken as no motion at all and
the impulse it delivers through a damper dropped. A source declares every
switch as a time event (Component.time_events), so the expression is
looked at across each of them: where it jumps (or, differentiated a second
time, where its rate jumps: a ramp's kinks under a mass) the rig is
refused. The test is a condition of the DAE (an expression of ``p`` that
must be >= 0, DAE.conditions), so that it holds for the parameters of each
run: a Sine's phase, a Step's height or a Table's interpolation decide it.

A kink (a ramp's, a linear table's) in a signal differentiated once is
fine: its rate jumps, a damper's force with it, but no impulse is lost.
"""
from __future__ import annotations

import casadi as ca

from ..casadi_helpers import subst

#: how far either side of a switch the expression is looked at, relative to the switch time
SIDE = 1e-7
#: a jump smaller than this part of the expression's size is rounding
JUMP = 1e-9


def jump_conditions(expr, t, switch, starts, level, p_all, params) -> list:
    """Conditions (expression of p >= 0, (where, text, names)) that refuse a
    jump of ``expr`` at each switch time of ``switch`` [(time expression,
    label, description)] after the run's start. The unknowns in ``expr``
    are held at ``starts`` (name -> start value; 0 where none), so that
    only its explicit dependence on time is left; ``level``: how often
    ``expr`` has been differentiated already (0: the signal itself, 1: its
    rate, None: either); ``p_all``: the names of p's symbols (parameters and the inputs'
    entries), ``params`` those of the free parameters (named in the
    message)."""
    if not switch or not ca.depends_on(expr, t):
        return []
    e = ca.SX(expr)
    for last in (False, False, True):   # a start may hold another unknown; then 0
        held = [s for s in ca.symvar(e) if s.name() not in p_all and not ca.is_equal(s, t)]
        if not held:
            break
        vals = [ca.SX(0.0 if last or starts.get(s.name()) is None else starts[s.name()])
                for s in held]
        e = subst(e, ca.vertcat(*held), ca.vertcat(*vals))
    if not ca.depends_on(e, t):
        return []
    out = []
    for c, label, text in switch:
        h = SIDE * ca.fmax(ca.fabs(c), 1e-6)
        r = [ca.substitute(e, t, c + k * h) for k in (-2.0, -1.0, 1.0, 2.0)]
        jump = (r[2] - r[1]) - (r[1] - r[0]) - (r[3] - r[2])
        size = ca.fmax(ca.fmax(ca.fabs(r[0]), ca.fabs(r[1])), ca.fmax(ca.fabs(r[2]), ca.fabs(r[3])))
        ok = JUMP * size + 1e-300 - ca.fabs(jump)
        # a switch at or before the start is not crossed; NaN (a law evaluated where it
        # is not defined) says nothing
        cond = ca.if_else(c <= 0, 1.0, ca.if_else(ok == ok, ok, 1.0))
        names = sorted({s.name() for s in ca.symvar(ca.vertcat(jump, c))} & params)
        out.append((cond, (label.rsplit(".", 1)[0] or label, _text(text or label, level), names)))
    return out


def _text(event, level) -> str:
    if level == 0:
        return (f"its signal jumps at {event}, but the rig differentiates it (a position it "
                "prescribes, whose velocity a damper needs): the jump's impulse would be lost; "
                "give it a rise time (a Ramp, a trace with a short ramp) or filter it (a "
                "FirstOrder block)")
    if level == 1:
        return (f"its rate jumps at {event}, but the rig differentiates it twice (a position it "
                "prescribes, whose acceleration a mass needs): the impulse there would be lost; "
                "filter it (a SecondOrder block) or drive a force")
    return (f"its signal or its rate jumps at {event}, where the rig differentiates it (a "
            "position it prescribes, whose velocity a damper or whose acceleration a mass "
            "needs): the impulse there would be lost; filter it (a FirstOrder block, a "
            "SecondOrder block under a mass) or drive a force")


class Jumps:
    """What the compiler's passes need to test the expressions they
    differentiate (``look``), and the conditions found (``conditions``, for
    DAE.conditions; one per source and switch)."""

    def __init__(self, t, switch, starts: dict, p_sym, params):
        self.t, self.switch, self.starts = t, list(switch), starts
        self.p_all = {p_sym[k].name() for k in range(p_sym.numel())}
        self.params = set(params)
        self.conditions, self._seen = [], set()

    def look(self, expr, level: int | None) -> None:
        """Add the conditions of ``expr``, about to be differentiated
        (``level``: how often it was already, None where not known)."""
        if not self.switch:
            return
        for cond in jump_conditions(expr, self.t, self.switch, self.starts, level, self.p_all,
                                    self.params):
            key = (cond[1][:2], str(cond[0]))   # the same test found again: once
            if key not in self._seen:
                self._seen.add(key)
                self.conditions.append(cond)
