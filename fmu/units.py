"""Unit strings of the rig ("N s/m^2.5", "m/s", "Pa", "1") to SI base-unit
exponents for FMI's UnitDefinitions."""
from __future__ import annotations

import re
from fractions import Fraction

BASE = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")

# symbol -> (exponents by BASE, factor to SI)
_DERIVED = {
    "kg": ({"kg": 1}, 1.0), "g": ({"kg": 1}, 1e-3), "t": ({"kg": 1}, 1e3),
    "m": ({"m": 1}, 1.0), "mm": ({"m": 1}, 1e-3), "cm": ({"m": 1}, 1e-2), "km": ({"m": 1}, 1e3),
    "s": ({"s": 1}, 1.0), "ms": ({"s": 1}, 1e-3), "min": ({"s": 1}, 60.0), "h": ({"s": 1}, 3600.0),
    "A": ({"A": 1}, 1.0), "K": ({"K": 1}, 1.0), "mol": ({"mol": 1}, 1.0), "cd": ({"cd": 1}, 1.0),
    "rad": ({"rad": 1}, 1.0), "deg": ({"rad": 1}, 3.141592653589793 / 180),
    "N": ({"kg": 1, "m": 1, "s": -2}, 1.0), "kN": ({"kg": 1, "m": 1, "s": -2}, 1e3),
    "MN": ({"kg": 1, "m": 1, "s": -2}, 1e6),
    "Pa": ({"kg": 1, "m": -1, "s": -2}, 1.0), "kPa": ({"kg": 1, "m": -1, "s": -2}, 1e3),
    "MPa": ({"kg": 1, "m": -1, "s": -2}, 1e6), "GPa": ({"kg": 1, "m": -1, "s": -2}, 1e9),
    "bar": ({"kg": 1, "m": -1, "s": -2}, 1e5),
    "J": ({"kg": 1, "m": 2, "s": -2}, 1.0), "W": ({"kg": 1, "m": 2, "s": -3}, 1.0),
    "Hz": ({"s": -1}, 1.0),
}

_TOKEN = re.compile(r"^([A-Za-z]+)(?:\^?\(?([-+]?\d+(?:\.\d+)?(?:/\d+)?)\)?)?$")


class UnitError(ValueError):
    """A unit string that parse() cannot read."""


def parse(unit: str) -> tuple[dict[str, Fraction], float]:
    """Exponents of the SI base units and the factor to SI of ``unit``.

    Grammar: products of symbols separated by spaces, ``*`` or ``.``, each with
    an optional exponent (``m^2``, ``m2``, ``s^-1``, ``m^1.5``); every ``/``
    divides by the whole product that follows it up to the next ``/``.
    ``"1"`` or ``""`` is dimensionless.
    """
    u = unit.strip()
    exps = {b: Fraction(0) for b in BASE}
    factor = 1.0
    if u in ("", "1", "-"):
        return exps, factor
    groups = u.replace("(", " ").replace(")", " ").split("/")
    for gi, group in enumerate(groups):
        sign = 1 if gi == 0 else -1
        for tok in re.split(r"[\s*·]+|(?<=[A-Za-z0-9])\.(?=[A-Za-z])", group.strip()):
            if not tok or tok == "1":
                continue
            mt = _TOKEN.match(tok)
            if not mt or mt.group(1) not in _DERIVED:
                raise UnitError(f"unknown unit '{tok}' in '{unit}'")
            e = Fraction(mt.group(2)) if mt.group(2) else Fraction(1)
            base, f = _DERIVED[mt.group(1)]
            for b, k in base.items():
                exps[b] += sign * k * e
            factor *= f ** float(sign * e)
    return exps, factor


def per_second(unit: str) -> str:
    """Name of the unit of the time derivative of a quantity in ``unit``."""
    u = unit.strip()
    if u in ("", "1", "-"):
        return "1/s"
    m = re.search(r"/s(?:\^?(\d+))?$", u)
    if m:
        k = int(m.group(1) or 1) + 1
        return u[: m.start()] + f"/s^{k}" if k > 1 else u
    if "/" in u:
        return f"{u}/s"
    return f"{u}/s"


def base_unit_attrs(unit: str) -> dict[str, str] | None:
    """Attributes of FMI's <BaseUnit>, or None if an exponent is not an
    integer (FMI 2.0 base-unit exponents are integers, so e.g. N/m^1.5 cannot
    be expressed)."""
    exps, factor = parse(unit)
    if any(e.denominator != 1 for e in exps.values()):
        return None
    attrs = {b: str(int(e)) for b, e in exps.items() if e != 0}
    if factor != 1.0:
        attrs["factor"] = repr(factor)
    return attrs
