"""The unknowns of a fit: which rig parameters are free, in what units the
optimiser sees them, and within which bounds.

Parameters span 1e0 to 1e10 (a mass, a stiffness), so the optimiser works on
scaled unknowns: ``z = ln(v / v_ref)`` for a positive parameter (a factor
is what is uncertain about a stiffness), ``z = (v - v_ref) / scale`` for
the others. A drop height ``X.h`` may stand for the impact speed ``X.v0`` of a
rig that has no ``h`` of its own: ``v0 = sqrt(2 g h)``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from pdbfs.components.laws import STANDARD_GRAVITY
from pdbfs.errors import ParameterError

#: default bounds: this factor either side of the start value (positive parameters)
CALIBRATION_RANGE = 100.0
DESIGN_RANGE = 10.0


@dataclass
class Unknown:
    """One unknown: a rig parameter (``target``), a drop height standing for
    an impact speed, or a quantity of the fit itself (time shift, offset)."""

    name: str
    unit: str
    description: str
    ref: float                 # start value
    lo: float
    hi: float
    log: bool                  # scaled as ln(v / ref)
    scale: float = 1.0         # for linear ones: z = (v - ref) / scale
    target: str | None = None  # rig parameter set by this unknown (None: not a rig parameter)
    height: bool = False       # a drop height for target = X.v0

    def z(self, v: float) -> float:
        return math.log(v / self.ref) if self.log else (v - self.ref) / self.scale

    def value(self, z: float) -> float:
        return self.ref * math.exp(z) if self.log else self.ref + self.scale * z

    def dvalue(self, z: float) -> float:
        """d value / d z."""
        return self.value(z) if self.log else self.scale

    def rig_value(self, v: float) -> float:
        """The value of the rig parameter this unknown sets."""
        return math.sqrt(2.0 * STANDARD_GRAVITY * v) if self.height else v

    def drig(self, v: float) -> float:
        return STANDARD_GRAVITY / math.sqrt(2.0 * STANDARD_GRAVITY * v) if self.height else 1.0

    @property
    def z_bounds(self) -> tuple[float, float]:
        return self.z(self.lo), self.z(self.hi)


def height_stands_for(dae, name) -> str | None:
    """The impact speed X.v0 a drop height ``name`` = X.h stands for, or None
    if ``name`` is no such height. A rig with a drop height of its own (the
    drop rig's ``h``) is refused: there X.v0 is a start speed on top of the fall."""
    names = set(dae.p_names)
    if name in names or not name.endswith(".h") or name[:-2] + ".v0" not in names:
        return None
    own = [p.name for p in dae.params
           if p.unit == "m" and p.description.lower().startswith("drop height")]
    if own:
        raise ParameterError(f"{name}: rig {dae.name} has a drop height of its own, {own[0]}; "
                             f"name {own[0]} ({name} would set {name[:-2]}.v0, a start speed "
                             "on top of the fall)")
    return name[:-2] + ".v0"


def parse_bounds(items) -> dict:
    """{name: (lo, hi)} from ``NAME=LO:HI`` strings (or a dict passed through)."""
    if isinstance(items, dict):
        return {k: tuple(map(float, v)) for k, v in items.items()}
    if isinstance(items, str):           # one bound, not read letter by letter
        items = [items]
    out = {}
    for item in items or []:
        name, sep, rng = item.partition("=")
        lo, sep2, hi = rng.partition(":")
        try:
            if not (sep and sep2 and name.strip()):
                raise ValueError
            pair = (float(lo), float(hi))
        except ValueError:
            raise ParameterError(f"--bounds {item!r}: expected NAME=LO:HI, e.g. oil.k=1e8:1e9") from None
        if name.strip() in out:          # the last would win without a word
            raise ParameterError(f"--bounds {name.strip()} given twice; give it once")
        out[name.strip()] = pair
    return out


def rig_unknowns(sim, free, *, bounds=None, start=None, fixed=None, factor=CALIBRATION_RANGE):
    """The Unknowns for the rig parameters named in ``free`` (a list, or a
    comma-separated string). ``bounds`` {name: (lo, hi)} and ``start``
    {name: value} override the defaults (the rig's value, a ``factor``
    either side); names in ``fixed`` (parameters held at a set value) may not
    be free."""
    dae = sim.dae
    if isinstance(free, str):
        free = [f.strip() for f in free.split(",") if f.strip()]
    free = list(free or [])
    if not free:
        raise ParameterError("no free parameters: name at least one, e.g. --free oil.k")
    dup = sorted({n for n in free if free.count(n) > 1})
    if dup:
        raise ParameterError(f"free parameter {dup[0]} is named twice")
    bounds, start, fixed = dict(bounds or {}), dict(start or {}), dict(fixed or {})
    extra = sorted(set(bounds) - set(free))
    if extra:
        raise ParameterError(f"bounds given for {extra[0]}, which is not a free parameter "
                             f"(free: {', '.join(free)})")
    p0 = sim.param_vector(fixed)
    info = {p.name: p for p in dae.params}
    out = []
    for name in free:
        if name in fixed:
            raise ParameterError(f"{name} is both free and fixed (set to {fixed[name]:g}); "
                                 "free it or set it, not both")
        height = False
        target = name
        if height_stands_for(dae, name):
            height, target = True, height_stands_for(dae, name)
            if target in free or target in fixed:
                raise ParameterError(f"{name} sets {target}: do not also free or set {target}")
        elif name not in info:
            sim.param_vector({name: 0.0})   # raises the usual error (calculated, or a hint)
        pi = info[target]
        v_rig = float(p0[dae.p_names.index(target)])
        if height:
            unit, desc = "m", f"Drop height giving the impact speed {target} = sqrt(2 g h)"
            ref = v_rig ** 2 / (2.0 * STANDARD_GRAVITY)
            positive = True
        else:
            unit, desc, ref, positive = pi.unit, pi.description, v_rig, pi.positive
        ref = float(start.get(name, ref))
        # a factor is what is uncertain about a quantity that cannot be negative
        log = (positive or (pi.min is not None and pi.min >= 0)) and ref > 0
        if height and name not in bounds and not ref > 0:
            raise ParameterError(f"{name}: {target} is {v_rig:g} m/s, a drop height of 0 m; "
                                 f"give --bounds {name}=LO:HI with LO > 0")
        if name in bounds:
            lo, hi = bounds[name]
            if not (math.isfinite(lo) and math.isfinite(hi)) or lo >= hi:
                raise ParameterError(f"bounds of {name}: lo = {lo:g} must be below hi = {hi:g}")
        elif log:
            lo, hi = ref / factor, ref * factor
        else:
            span = abs(ref) * (factor - 1.0) if ref else 1.0
            lo, hi = ref - span, ref + span
        if not height:
            if pi.min is not None:
                lo = max(lo, pi.min)
            if pi.max is not None:
                hi = min(hi, pi.max)
        if height and not lo > 0:      # sqrt(2 g h): a height is scaled by factors, never 0
            raise ParameterError(f"{name}: the drop height must stay above 0 m (it starts at "
                                 f"{ref:g} m, bounds from {lo:g} m); give --bounds {name}=LO:HI "
                                 "with LO > 0")
        if log and lo <= 0:
            raise ParameterError(f"bounds of {name}: lo = {lo:g} {unit}; it must be > 0")
        if lo >= hi:
            raise ParameterError(f"bounds of {name}: [{lo:g}, {hi:g}] {unit} is empty within "
                                 "the parameter's own limits")
        if not lo <= ref <= hi:          # start inside the bounds
            ref = math.sqrt(lo * hi) if log else 0.5 * (lo + hi)
        out.append(Unknown(name, unit, desc, ref, lo, hi, log, abs(ref) or 1.0, target, height))
    return out, p0
