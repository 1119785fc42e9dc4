"""The two least-squares problems of calibration and design, as residual
functions of the scaled unknowns with exact Jacobians:

* CurveProblem: the model's signal, moved by a trigger shift and a sensor
  offset if asked, against a curve sampled at its own times (a measured
  trace, or a target pulse);
* FeatureProblem: pulse features (peak, time of peak, duration) against
  target values, relative.
"""
from __future__ import annotations

import numpy as np

from .features import pulse_features
from .signal_model import SignalModel
from .free_parameters import Unknown

SHIFT, OFFSET = "trace.shift", "trace.offset"


def offset_unknowns(trace, model_curve, unit) -> list[Unknown]:
    """A trigger time shift (model at t - shift) and a constant sensor
    offset, started where the trace and the model first pass 10 % of their
    peaks, and at the trace's baseline before that."""
    t, y = trace.t, trace.y
    base = float(np.median(y[: max(len(y) // 50, 3)]))
    span = trace.span
    tm, ym = model_curve
    k_tr = int(np.argmax(y - base >= 0.1 * (np.max(y) - base)))
    k_m = int(np.argmax(ym >= 0.1 * np.max(ym)))
    shift0 = float(t[k_tr] - tm[k_m])
    amp = float(np.max(np.abs(y))) or 1.0
    return [Unknown(SHIFT, "s", "Time of the trace at the model's t = 0 (trigger delay)", shift0,
                    shift0 - 0.1 * span, shift0 + 0.1 * span, False, 1e-3),
            Unknown(OFFSET, unit, "Constant offset of the sensor", base, base - 0.2 * amp,
                    base + 0.2 * amp, False, amp)]


class CurveProblem:
    """Residuals (model - curve) / scale at the curve's times. ``held``
    {name: value} keeps some unknowns out of the fit at fixed values; the
    scaled vector z holds the others, in order."""

    def __init__(self, model: SignalModel, unknowns: list[Unknown], trace, scale: float,
                 held: dict | None = None):
        self.model, self.all, self.trace, self.scale = model, unknowns, trace, scale
        self.held = dict(held or {})
        self.unknowns = [u for u in unknowns if u.name not in self.held]
        self.rig_cols = {u.name: k for k, u in enumerate(u for u in unknowns if u.target)}

    def values(self, z) -> dict:
        """Every unknown's value by name for the scaled vector ``z`` (held ones included)."""
        it = iter(z)
        return {u.name: self.held[u.name] if u.name in self.held else u.value(next(it))
                for u in self.all}

    def curve(self, z, sens=True):
        """(model at the curve's times, d model / d z)."""
        v = self.values(z)
        s = self.model(np.array([u.rig_value(v[u.name]) for u in self.all if u.target]),
                       sens=sens)
        y, ydot, dy = s.at(self.trace.t - v.get(SHIFT, 0.0))
        J = np.zeros((len(y), len(z)))
        for k, (u, zk) in enumerate(zip(self.unknowns, z)):
            if u.target:
                J[:, k] = dy[:, self.rig_cols[u.name]] * u.drig(v[u.name]) * u.dvalue(zk)
            elif u.name == SHIFT:
                J[:, k] = -ydot * u.dvalue(zk)
            else:   # OFFSET
                J[:, k] = u.dvalue(zk)
        return y + v.get(OFFSET, 0.0), J

    def __call__(self, z):
        y, J = self.curve(z)
        return (y - self.trace.y) / self.scale, J / self.scale


class FeatureProblem:
    """Residuals (feature - target) / |target| for the features asked for."""

    def __init__(self, model: SignalModel, unknowns: list[Unknown], targets: dict):
        self.model, self.unknowns, self.targets = model, unknowns, dict(targets)
        self.names = list(self.targets)

    def values(self, z) -> np.ndarray:
        """The unknowns' values for the scaled vector ``z``."""
        return np.array([u.value(zi) for u, zi in zip(self.unknowns, z)])

    def features(self, z, sens=True):
        """(features, their gradients in z, the signal) at ``z``."""
        v = self.values(z)
        s = self.model(np.array([u.rig_value(vi) for u, vi in zip(self.unknowns, v)]), sens=sens)
        feats, grads = pulse_features(s, self.names)
        chain = np.array([u.drig(vi) * u.dvalue(zi) for u, vi, zi in zip(self.unknowns, v, z)])
        return feats, {k: g * chain for k, g in grads.items()}, s

    def __call__(self, z):
        feats, grads, _ = self.features(z)
        r = np.array([(feats[k] - t) / abs(t) for k, t in self.targets.items()])
        J = np.array([grads[k] / abs(t) for k, t in self.targets.items()])
        return r, J
