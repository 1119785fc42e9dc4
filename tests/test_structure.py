"""The structural analysis builds the same DAEs as before its rewrite for
large rigs (same states, same equations to 1e-12), and its work grows
linearly with the rig."""
import json

import numpy as np
import pytest

from dae_fingerprint import REFERENCE, fingerprint, rigs

REF = json.loads(REFERENCE.read_text())


@pytest.mark.parametrize("name", sorted(REF))
def test_the_same_dae_as_before(name):
    got = fingerprint(rigs()[name]().compile())
    want = REF[name]
    for k in ("x", "z", "p", "y", "events", "calculated"):
        assert got[k] == want[k], (name, k)
    for a, b in zip(got["evals"], want["evals"]):
        for k in ("ode", "alg", "out", "events", "start"):
            assert np.allclose(a[k], b[k], rtol=1e-12, atol=1e-12 * (1 + np.abs(b[k]).max(initial=0))), (name, k)
