"""A parameter as the page offers it (a field and a slider, logarithmic
for stiffness and damping), the order the page lists them in, and the
page's reading of a field's text."""
from __future__ import annotations

import math
from dataclasses import dataclass

from pdbfs.components.laws import STANDARD_GRAVITY
from pdbfs.errors import ParameterError

from .numbers import DERIVED_DIGITS, GIVEN_DIGITS, number

#: units whose values span decades: stiffness and damping get a logarithmic slider
LOG_UNITS = ("N/m", "N.s/m")


@dataclass(frozen=True)
class Control:
    """A parameter as the page offers it: a number field and a slider."""

    name: str
    unit: str
    description: str
    default: float
    lo: float              # slider range, in the parameter's value (not its log)
    hi: float
    log: bool
    step: float            # slider step, in slider units (log10 of the value when log)
    derived: str = ""      # "hammer.v0" for a drop height that stands for it

    def to_slider(self, value: float) -> float:
        """The slider position of ``value`` (log10 of it on a logarithmic slider)."""
        if self.log:
            return math.log10(value) if value > 0 else math.log10(self.lo)
        return value

    def from_slider(self, s: float) -> float:
        """The value at slider position ``s``."""
        return 10.0 ** s if self.log else s

    def slider_value(self, s: float) -> float:
        """The value a slider position stands for, to the slider's own
        resolution (a step of a linear slider, 4 digits of a logarithmic
        one): the field shows it, and it is what is simulated."""
        v = self.from_slider(s)
        if not math.isfinite(v):
            return v
        if self.log:
            return float(number(v, DERIVED_DIGITS))
        return float(number(round(v / self.step) * self.step, GIVEN_DIGITS))

    def slider_range(self, value: float | None = None) -> tuple[float, float]:
        """The slider's (min, max), widened to hold ``value`` (up to a million
        steps: a larger value leaves the slider at its end, the field holds it)."""
        lo, hi = self.to_slider(self.lo), self.to_slider(self.hi)
        if value is not None and math.isfinite(value) and (value > 0 or not self.log):
            s = self.to_slider(value)
            reach = 1e6 * self.step
            s = min(max(s, lo - reach), hi + reach)
            lo, hi = min(lo, _floor(s, self.step)), max(hi, _ceil(s, self.step))
        return lo, hi


def _floor(x, step):
    q = x / step
    return round(math.floor(q) * step, 12) if math.isfinite(q) else x


def _ceil(x, step):
    q = x / step
    return round(math.ceil(q) * step, 12) if math.isfinite(q) else x


def linear_range(default: float, pmin):
    """A round range about a default: 0 .. about 2.5 x default (or both signs)."""
    if default == 0:
        return (0.0, 1.0, 0.01) if pmin is not None and pmin >= 0 else (-1.0, 1.0, 0.01)
    mag = 10.0 ** math.floor(math.log10(abs(default) * 2.5))
    top = math.ceil(abs(default) * 2.5 / mag) * mag
    step = 10.0 ** (math.floor(math.log10(top)) - 2)
    lo = 0.0 if default > 0 else -top
    hi = top if default > 0 else 0.0
    if pmin is not None and pmin > lo:
        lo = _floor(pmin, step)
    return lo, hi, step


def control_of(info) -> Control:
    """The Control of a parameter (ParamInfo): logarithmic for units that span decades."""
    log = info.unit.startswith(LOG_UNITS) and info.value > 0
    if log:
        c = math.log10(info.value)
        lo, hi = 10.0 ** _floor(c - 1, 0.01), 10.0 ** _ceil(c + 1, 0.01)
        return Control(info.name, info.unit, info.description, info.value, lo, hi, True, 0.01)
    lo, hi, step = linear_range(info.value, info.min)
    if info.max is not None:
        hi = min(hi, info.max)
    return Control(info.name, info.unit, info.description, info.value, lo, hi, False, step)


def drop_height(v0: float) -> float:
    """The drop height whose free fall gives ``v0`` (impact_velocity inverted)."""
    return v0 * v0 / (2.0 * STANDARD_GRAVITY)


def parse_number(name: str, text) -> float:
    """A field's text as a number, or the one-line error the command line gives."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    try:
        return float(str(text).strip())
    except ValueError:
        raise ParameterError(f"{name}: {str(text).strip()!r} is not a number") from None


#: the last part of the names of start values and position offsets: they
#: rarely change, and the page lists them last
START = ("s0", "v0", "p0", "s_rel0")
#: the page's groups of parameters that are no component's
KEY, START_GROUP = "key", "start"


def is_start(name: str) -> bool:
    """Whether ``name`` is a start value or position offset (``hammer.s0``)."""
    return name.rsplit(".", 1)[-1] in START


def page_groups(controls: list, key=()) -> list:
    """The controls in the order the page lists them, as (group, controls):
    the rig's ``key`` parameters first (in their order), then the others
    by component (in the rig's order; rig-level ones under ``""``), then
    the start values and position offsets. A control that stands for
    another (a drop height for an impact speed) follows it."""
    follows = {c.derived: c for c in controls if c.derived}     # impact speed -> drop height
    stands = {c.name: c.derived for c in controls if c.derived}   # drop height -> impact speed
    plain = [c for c in controls if not c.derived]
    names = {c.name for c in plain}
    key = [stands.get(n, n) for n in key]
    key = [n for k, n in enumerate(key) if n in names and n not in key[:k]]
    groups: dict = {KEY: [c for n in key for c in plain if c.name == n]}
    start = []
    for c in plain:
        if c.name in key:
            continue
        if is_start(c.name):
            start.append(c)
        else:
            groups.setdefault(c.name.split(".", 1)[0] if "." in c.name else "", []).append(c)
    groups[START_GROUP] = start
    out = []
    for group, cs in groups.items():
        cs = [x for c in cs for x in ([c, follows[c.name]] if c.name in follows else [c])]
        if cs:
            out.append((group, cs))
    return out
