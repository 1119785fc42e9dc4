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


def test_a_structural_zero_is_a_row_of_zeros_not_left_out():
    """The rate of a constant output is a structural zero: its row was left
    out and the rows after it moved up (a summary read one variable's rate as
    another's)."""
    import casadi as ca
    import numpy as np
    from pdbfs.simulation.setup.vectorize import vectorize
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [ca.vertcat(ca.SX(0), x[0] * x[1], ca.SX(0), 2 * x[1])])
    X = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    out = vectorize(f)(X)[0]
    assert out.shape == (4, 3)
    assert np.array_equal(out, f.map(3)(X).full())
