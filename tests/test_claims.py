"""Every figure in the claims table (tests/claims.py) is what the code gives now."""
import re
from pathlib import Path

import pytest

from claims import CLAIMS

ROOT = Path(__file__).resolve().parents[1]


def _flat(text: str) -> str:      # markdown wraps sentences anywhere
    return re.sub(r"\s+", " ", text)


@pytest.mark.parametrize("claim", CLAIMS, ids=lambda c: f"{c.doc}: {c.text[:40]}")
def test_stated_figure_is_computed(claim):
    stated = _flat((ROOT / claim.doc).read_text())
    sentence = claim.text.format(**claim.values())
    assert _flat(sentence) in stated, f"{claim.doc} should say: {sentence}"
