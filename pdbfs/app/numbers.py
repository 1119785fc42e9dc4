"""How the page writes numbers: to the digits they carry, in the units an
engineer reads (MPa, kN, mm, ms), with the unit beside; every text a field
shows is one that float() reads back."""
from __future__ import annotations

import math

#: how the page shows SI units: (factor, label)
SHOWN = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "s": (1e3, "ms")}

#: significant digits of what the page computes or derives: a run's figures
#: (within 2e-6 of a converged run at the default tolerance), a designed value
RESULT_DIGITS = 5
#: ... of a setting derived from another (the drop height of an impact speed)
#: or set by a logarithmic slider (its steps are 2.3 % apart)
DERIVED_DIGITS = 4
#: ... of a setting as given (a default, a typed value): all of Table 1's digits
GIVEN_DIGITS = 6
#: ... of a slider's end marks
MARK_DIGITS = 3


def number(v, digits: int = GIVEN_DIGITS) -> str:
    """``v`` to ``digits`` significant digits, trailing zeros dropped, in plain
    notation from 1e-4 up to 1e6 (``2950``, ``0.38``) and as ``2.228e8``
    beyond (no ``+``, no leading zeros in the exponent)."""
    if v is None:
        return "n/a"
    if isinstance(v, bool) or not isinstance(v, (int, float)) and not hasattr(v, "__float__"):
        return str(v)
    v = float(v)
    if not math.isfinite(v):
        return "n/a" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    text = f"{v:.{digits}g}"
    if "e" in text and 1e-4 <= abs(float(text)) < 1e6:     # 8e+03 -> 8000
        text = f"{float(text):f}".rstrip("0").rstrip(".")
    mant, e, exp = text.partition("e")
    return f"{mant}e{int(exp)}" if e else text


def shown_unit(unit: str) -> tuple:
    """(factor, label) of an SI unit as the page shows it (``1``: no label)."""
    return SHOWN.get(unit, (1.0, "" if unit in ("1", "") else unit))


def quantity(v, unit: str, digits: int = RESULT_DIGITS) -> str:
    """A value (SI) in the unit the page shows, the unit beside: ``92.117 MPa``."""
    if v is None or isinstance(v, float) and not math.isfinite(v):
        return "n/a"
    f, label = shown_unit(unit)
    return f"{number(v * f, digits)} {label}".strip()


def with_std(v, std, digits: int = RESULT_DIGITS) -> str:
    """A fitted value and its standard deviation, the value to the digit its
    deviation allows (the deviation to 2 digits; the value to 2 .. 8 digits):
    ``3.0001e8 ± 1.2e4``."""
    if v is None:
        return "undetermined"
    if std is None or not math.isfinite(std) or std <= 0 or v == 0 or not math.isfinite(v):
        return number(v, digits)
    place = math.floor(math.log10(std)) - 1           # last digit of the deviation
    keep = min(max(math.floor(math.log10(abs(v))) - place + 1, 2), 8)
    value = number(v, keep)
    # the deviation in the value's notation: 2.9944e8 ± 4.5e5, not ± 450000
    dev = number(std, 2) if "e" not in value else f"{std:.1e}".replace("e+0", "e").replace(
        "e+", "e").replace("e-0", "e-")
    return f"{value} ± {dev}"


def short_description(text: str) -> str:
    """The first phrase of a description (before a comma, semicolon or
    bracket), lower case: ``Compressive force, positive when ...`` ->
    ``compressive force``."""
    head = text
    for sep in (",", ";", " (", ":"):
        head = head.split(sep, 1)[0]
    head = head.strip().rstrip(".")
    if not head:
        return text
    # lower-case the first letter unless the first word is an acronym (RMS)
    first = head.split(" ", 1)[0]
    return head if first.isupper() and len(first) > 1 else head[0].lower() + head[1:]
