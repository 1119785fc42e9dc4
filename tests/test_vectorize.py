import casadi as ca
import numpy as np

from pdbfs.models import paper_rig
from pdbfs.simulation.setup.vectorize import vectorize


def test_numpy_replay_matches_casadi_on_every_output():
    dae = paper_rig().compile()
    f = ca.Function("out", [dae.t, dae.x, dae.z, dae.p], [dae.y, dae.ode, dae.events])
    fast = vectorize(f)
    assert fast is not None
    rng = np.random.default_rng(1)
    n = 500
    t = rng.uniform(0, 0.02, (1, n))
    X = rng.normal(0, 1e-3, (dae.x.numel(), n)) * np.array([[1], [1e3], [1], [1e3], [1], [1e3]])
    p = dae.p_default()
    ref = f.map(n)(t, X, ca.DM(0, n), p)
    got = fast(t, X, np.zeros((0, n)), p.reshape(-1, 1))
    for r, g in zip(ref, got):
        assert np.allclose(r.full(), g, rtol=1e-13, atol=0)


def test_unsupported_operation_falls_back():
    x = ca.SX.sym("x")
    assert vectorize(ca.Function("f", [x], [ca.erf(x)])) is None
