"""Every figure in the claims table (tests/claims.py) is what the code gives
now, to the precision its computation supports: the figure as stated
(half a unit of its last digit) plus, for an optimizer's result, its own
uncertainty (claims.Claim.tolerance)."""
import re
import string
from pathlib import Path

import pytest

from claims import CLAIMS

ROOT = Path(__file__).resolve().parents[1]
NUMBER = r"[-+]?\d[\d,]*(?:\.\d+)?(?:e[-+]?\d+)?"


def _flat(text: str) -> str:      # markdown wraps sentences anywhere
    return re.sub(r"\s+", " ", text)


def pattern(text: str) -> str:
    """A regex of the sentence, each placeholder a named number."""
    out = []
    for lit, name, spec, _ in string.Formatter().parse(text):
        out.append(r"\s+".join(re.escape(w) for w in re.split(r"\s+", lit)))
        if name is not None:
            out.append(f"(?P<{name}>{NUMBER})")
    return "".join(out)


def half_unit(stated: str) -> float:
    """Half a unit of the stated figure's last digit."""
    mantissa, _, exp = stated.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 0.5 * 10.0 ** (int(exp or 0) - decimals)


def digits(stated: str) -> int:
    mantissa = stated.lower().partition("e")[0]
    return len(mantissa.split(".")[1]) if "." in mantissa else 0


def test_half_unit_and_pattern():
    assert half_unit("92.1") == pytest.approx(0.05) and half_unit("1.1e-8") == pytest.approx(5e-10)
    assert half_unit("3.19957") == pytest.approx(5e-6) and half_unit("14") == 0.5
    m = re.search(pattern("peak {p:.1f} MPa at {t:.2f} ms"), "a peak 92.1 MPa at 5.57 ms.")
    assert m.group("p") == "92.1" and m.group("t") == "5.57"


@pytest.mark.parametrize("claim", CLAIMS, ids=lambda c: f"{c.doc}: {c.text[:40]}")
def test_stated_figure_is_computed(claim):
    stated = _flat((ROOT / claim.doc).read_text())
    m = re.search(pattern(claim.text), stated)
    assert m, f"{claim.doc} no longer says: {claim.text}"
    values = claim.values()
    tolerance = claim.tolerance(values) if claim.tolerance else {}
    for _, name, spec, _ in (f for f in string.Formatter().parse(claim.text) if f[1]):
        text = m.group(name).replace(",", "")
        precision = re.search(r"\.(\d+)[fe]", spec)
        if precision:            # stated to the digits the claim computes it to
            assert digits(text) == int(precision.group(1)), (name, text, spec)
        value = values[name]
        allowed = half_unit(text) + tolerance.get(name, 0.0) + 1e-9 * abs(value)
        assert abs(float(text) - value) <= allowed, \
            f"{claim.doc}: {name} stated {text}, computed {value:.6g} (allowed {allowed:.2g})"
