"""A campaign's arguments checked and made ready, before any blow is run:
the rig and its pressure, the blows and their period, the start
temperatures and the thermal network that carries them between blows, the
schedule, the operator's rule and the breech. Bad input raises a
``pdbfs.errors`` exception whose message is one line naming the culprit."""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from pdbfs.errors import ParameterError, plain
from pdbfs.fatigue import Breech
from pdbfs.simulation import Simulator
from pdbfs.simulation.setup.settings import default_atol, default_rtol, mapping

from ..blows import height_parameter
from .heat import HeatNetwork, Pause
from .plan import HoldPeak, Schedule, rule_of, rule_spec

if TYPE_CHECKING:
    from pdbfs.rig import Rig

#: how a blow's damage is read: its peak (rest -> peak -> rest) or its whole history
DAMAGE_FROM = ("peak", "history")
#: the oil's heat capacitor, by name, in pdbfs's thermal rigs
OIL = "oil_heat.T"


@dataclass
class Setup:
    """What every blow of a campaign is run with (made by :func:`prepare`)."""

    rig: Rig
    sim: Simulator
    name: str
    blows: int
    period: float
    t_blow: float
    n_out: int                 # output points of a blow whose history is read
    pressure: str
    fixed: dict                # the parameters every blow is given
    settings: list             # the setting columns: striker, schedule's, rule's
    start: dict                # the settings' values at the first blow
    network: HeatNetwork | None
    pause: Pause | None
    states: list               # the capacitors' temperatures (network order)
    T0: np.ndarray             # their values at the campaign's start, K
    t0_names: list             # the parameters that start a blow at them
    oil: int | None            # the oil's index in states
    schedule: Schedule | None
    rule: Any
    breech: Breech
    damage_from: str
    check_every: int
    run: dict                  # rtol, atol, method, backend of each blow
    rest: Any                  # parameter vectors (rows) -> the rest pressures, or None

    def spec(self) -> dict:
        """What identifies the campaign (a saved one resumes only as itself)."""
        return {"kind": "campaign", "rig": self.name, "period": self.period,
                "t_blow": self.t_blow, "params": self.fixed,
                "temperatures": dict(zip(self.states, self.T0.tolist())),
                "schedule": None if self.schedule is None else self.schedule.key(),
                "rule": rule_spec(self.rule), "damage": self.damage_from,
                "check_every": self.check_every, "run": self.run,
                "breech": spec_of_breech(self.breech)}


def spec_of_breech(breech: Breech) -> list:
    """A breech's dimensions and S-N curve, as a campaign's manifest holds them."""
    c, s = breech.cylinder, breech.curve
    return [c.inner_radius, c.outer_radius, s.m, s.stress_range_ref, s.cycles_ref,
            s.endurance_limit]


def prepare(rig: Rig | str, blows: Any, period: Any, schedule=None, rule=None, params=None,
            temperatures=None, breech=None, damage: str = "peak", check_every: Any = 500,
            t_blow: Any = None, oil: str | None = None, rtol=None, atol=None,
            method: str = "auto", backend: str = "auto") -> Setup:
    """The campaign's Setup, every argument checked (see :func:`campaign`)."""
    if isinstance(rig, str):
        from pdbfs.models import RIGS
        if rig not in RIGS:
            raise ParameterError(f"unknown rig {rig!r}; choose one of {', '.join(RIGS)}")
        rig = RIGS[rig]()
    if isinstance(blows, bool) or not isinstance(blows, (int, np.integer)) or blows < 1:
        raise ParameterError(f"campaign: blows = {plain(blows)}: a campaign has 1 blow or more "
                             "(a whole number)")
    period = _seconds(period, "period", "the time from one blow to the next")
    t_blow = _seconds(getattr(rig, "default_t_end", 0.02) if t_blow is None else t_blow,
                      "t_blow", "each blow's simulated time")
    if not t_blow < period:
        raise ParameterError(f"campaign: the period {period:g} s is not longer than a blow's "
                             f"simulated time {t_blow:g} s")
    if damage not in DAMAGE_FROM:
        raise ParameterError(f"campaign: damage = {damage!r}; choose peak (each blow's peak "
                             "pressure) or history (its whole pressure history)")
    if isinstance(check_every, bool) or not isinstance(check_every, (int, np.integer)) \
            or check_every < 0:
        raise ParameterError(f"campaign: check_every = {plain(check_every)} must be a whole "
                             "number of blows, 0 or more (0: no blow's history is read)")
    if breech is not None and not isinstance(breech, Breech):
        raise ParameterError(f"campaign: breech must be a pdbfs.fatigue.Breech, not "
                             f"{type(breech).__name__}")
    sim = Simulator.of(rig)
    dae = sim.dae
    pressure = (getattr(dae, "signals", {}) or {}).get("pressure")
    if not pressure:
        raise ParameterError(f"rig {dae.name} names no pressure (summary_signals): its blows "
                             "have no peak pressure and no damage")
    given = mapping(params, "params")
    sim.param_vector(given)                    # unknown names and bad values refused now
    fixed = {k: float(v) for k, v in given.items()}
    sim.check_settings(default_rtol(method, rtol), atol, method, None, backend=backend)
    values = {**{p.name: p.value for p in dae.params}, **fixed}
    network = HeatNetwork.of(rig, values)
    states = network.states if network is not None else []
    temps = mapping(temperatures, "temperatures", "'oil_heat.T': 303.15")
    if network is None and (temps or oil is not None):
        raise ParameterError(f"rig {dae.name} has no thermal network: "
                             f"{'temperatures=' if temps else 'oil='} has no temperature to set")
    for name, value in temps.items():
        if name not in states:
            raise ParameterError(f"temperatures: {name!r} is not a heat capacitor's temperature "
                                 f"of rig {dae.name}; choose {', '.join(states)}")
        if f"{name[:-2]}.T0" in fixed:
            raise ParameterError(f"temperatures: {name} is given, and params gives "
                                 f"{name[:-2]}.T0 too; give it once")
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ParameterError(f"temperatures: {name} = {plain(value)} K must be a positive "
                                 "number (an absolute temperature)")
    t0_names = [f"{s[:-2]}.T0" for s in states]
    T0 = np.array([float(temps.get(s, values[n])) for s, n in zip(states, t0_names)])
    if oil is not None and oil not in states:
        raise ParameterError(f"oil = {oil!r} is not a heat capacitor's temperature of rig "
                             f"{dae.name}; choose {', '.join(states)}")
    oil = oil if oil is not None else (OIL if OIL in states else None)
    refused = {n: "is a parameter of the thermal network, which stays as it is for the "
               "campaign" for n in (network.parameters if network is not None else [])}
    refused.update({n: "is a start temperature: the blows before set it" for n in t0_names})
    plan = Schedule.of(schedule, dae, int(blows), refused)
    both = sorted(set(plan.columns) & set(fixed)) if plan is not None else []
    if both:
        raise ParameterError(f"campaign: {', '.join(both)} is given in params and in the "
                             "schedule; give it to one of them")
    rule = _rule(rule, dae, plan, refused)
    striker = height_parameter(dae)
    settings = list(dict.fromkeys(([striker[0]] if striker else [])
                                  + (list(plan.columns) if plan else [])
                                  + ([rule.parameter] if isinstance(rule, HoldPeak) else [])))
    start = {n: values[n] for n in settings}
    if plan is not None:
        start.update(plan.row(0))
    T0_params = dict(zip(t0_names, T0.tolist()))
    run = _run_settings(sim, {**fixed, **start, **T0_params}, t_blow, rtol, atol, method,
                        backend)
    return Setup(rig, sim, dae.name, int(blows), period, t_blow,
                 int(getattr(rig, "default_n_out", 2001)), pressure, fixed, settings, start,
                 network, network.pause(period - t_blow) if network is not None else None,
                 states, T0, t0_names, states.index(oil) if oil is not None else None,
                 plan, rule, breech if breech is not None else Breech(), damage,
                 int(check_every), run, rest_pressure(dae, pressure))


def _run_settings(sim, params, t_blow, rtol, atol, method, backend) -> dict:
    """One method, back end and tolerance for every blow, chosen at the first
    (as a sweep does): "auto" is not decided again at each new temperature."""
    from pdbfs.simulation.run.backends import backend_for_method
    p = sim.param_vector(params)
    resolved = sim.resolve_backend(backend)
    method = sim.resolve_method(method, p, sim.start_vector(p), t_blow, resolved)
    backend = backend_for_method(sim, backend, resolved, method)
    rtol = default_rtol(method, rtol)
    return {"rtol": rtol, "atol": default_atol(rtol, atol), "method": method, "backend": backend}


def rest_pressure(dae, pressure: str):
    """A function of parameter vectors (rows) giving the rig's pressure at
    its declared start, each blow's rest pressure, evaluated for many blows
    at once; None where the start is not the declared one or the pressure
    is not a function of the states and parameters alone (then each blow's
    Result is read)."""
    import casadi as ca

    from pdbfs.simulation.setup.initialize import needs_solving
    from pdbfs.simulation.setup.vectorize import vectorize
    if not dae.is_ode or needs_solving(dae, None) or getattr(dae, "reduced_starts", None):
        return None
    at_start = ca.substitute(dae.y[dae.y_names.index(pressure)], ca.vertcat(dae.t, dae.x),
                             ca.vertcat(0.0, dae.x0))
    f = ca.Function("rest_pressure", [dae.p], [at_start])
    fast = vectorize(f)
    if fast is not None:
        return lambda P: fast(np.asarray(P, dtype=float).T)[0][0]
    return lambda P: np.asarray(f.map(len(P))(np.asarray(P, dtype=float).T)).ravel()


def _seconds(value, name, what) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)) \
            or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"campaign: {name} = {plain(value)} s: {what} must be a positive "
                             "number of seconds")
    return float(value)


def _rule(rule, dae, plan, refused):
    """The operator's rule, checked: a text names one, a HoldPeak gets the rig's striker."""
    if rule is None:
        return None
    if isinstance(rule, str):
        rule = rule_of(rule)
    if isinstance(rule, HoldPeak):
        rule = rule.bound(dae)
        if rule.parameter in refused:
            raise ParameterError(f"hold-peak: {rule.parameter} {refused[rule.parameter]}")
        if plan is not None and rule.parameter in plan.columns:
            raise ParameterError(f"hold-peak adjusts {rule.parameter}, which the schedule sets "
                                 "too; give it to one of them")
        return rule
    if not callable(rule):
        raise ParameterError(f"campaign: rule must be a function of the blows so far (or a "
                             f"HoldPeak), not {type(rule).__name__}")
    return rule


def rule_changes(changes: Any, setup: Setup, blow: int) -> dict:
    """A rule's answer for blow ``blow`` (from 1), checked: {parameter: value} or None."""
    if changes is None:
        return {}
    if not isinstance(changes, Mapping):
        raise ParameterError(f"campaign: the rule's answer before blow {blow} is a "
                             f"{type(changes).__name__}, not a dict of parameter values")
    out = {}
    dae = setup.sim.dae
    for name, value in changes.items():
        if name not in dae.p_names:
            raise ParameterError(f"campaign: the rule sets {name!r} before blow {blow}, which "
                                 f"is not a parameter of rig {dae.name}")
        if name in setup.t0_names or (setup.network and name in setup.network.parameters):
            raise ParameterError(f"campaign: the rule sets {name} before blow {blow}, which "
                                 "the campaign keeps for itself")
        try:
            v = float(value)
        except (TypeError, ValueError):
            v = math.nan
        if not math.isfinite(v):
            raise ParameterError(f"campaign: the rule sets {name} = {plain(value)} before blow "
                                 f"{blow}: not a finite number")
        out[name] = v
    return out
