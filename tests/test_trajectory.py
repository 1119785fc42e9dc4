"""A rig as a differentiable CasADi Function of its parameters."""
import casadi as ca
import numpy as np
import pytest

import pdbfs
from pdbfs.models import paper_rig

TIGHT = dict(rtol=1e-10, atol=1e-13)


def test_trajectory_function_matches_simulate():
    rig = paper_rig()
    f = pdbfs.trajectory_function(rig, ["oil.pressure", "piston.s"], n_out=101,
                                  inputs=["hammer.v0"])
    y = f(4.23).full()
    # a tight run: the function integrates through the kinks (it is differentiated), at the
    # default tolerances, where simulate() locates them (measured 1.4e-7 of the peak apart)
    res = rig.simulate(n_out=101, params={"hammer.v0": 4.23}, rtol=1e-12)
    assert np.allclose(y[0], res["oil.pressure"], rtol=0, atol=1e-6 * res["oil.pressure"].max())
    assert np.allclose(y[1], res["piston.s"], rtol=0, atol=1e-6 * res["piston.s"].max())


def test_sensitivities_agree_with_finite_differences():
    rig = paper_rig()
    names = ["oil.k", "seal.c", "contact.k"]
    p0 = np.array([2.228e8, 2.556e4, 5.958e10])
    f = pdbfs.trajectory_function(rig, "oil.pressure", n_out=41, inputs=names, **TIGHT)
    p = ca.MX.sym("p", 3)
    J = ca.Function("J", [p], [ca.jacobian(f(p), p)])(p0).full()
    k = 12                                   # t = 6 ms, near the peak
    for j in range(3):
        h = 1e-5 * p0[j]
        up, down = p0.copy(), p0.copy()
        up[j] += h
        down[j] -= h
        fd = (f(up).full().ravel()[k] - f(down).full().ravel()[k]) / (2 * h)
        assert J[k, j] == pytest.approx(fd, rel=2e-3), names[j]
    assert np.all(np.isfinite(J))


def test_bad_names_are_named():
    with pytest.raises(pdbfs.ParameterError, match="unknown output.*oil.presure"):
        pdbfs.trajectory_function(paper_rig(), ["oil.presure"])
    with pytest.raises(pdbfs.ParameterError, match="unknown parameter 'oil.kk'.*oil.k"):
        pdbfs.trajectory_function(paper_rig(), ["oil.pressure"], inputs=["oil.kk"])
