"""Index reduction to any index (Pantelides' algorithm, dummy derivatives)
against physics: two masses on springs tied by a nonlinear cam,
s2 = a*s1 + b*s1^2 (index 3: a constraint on positions), against the ODE
reduced by hand (Lagrange's equation in s1) integrated by scipy; the
constraint along the solution; energy; and the refusals."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdbfs.components import Cam, Fixed, Force, Mass, Spring
from pdbfs.errors import ModelError
from pdbfs.rig import Rig

M1, M2, K1, K2, A, B, F = 2.0, 0.5, 100.0, 300.0, 0.8, 0.5, 7.0
S1, V1 = 0.1, 0.5
S2, V2 = A * S1 + B * S1 ** 2, (A + 2 * B * S1) * V1
TIGHT = dict(rtol=1e-11, atol=1e-13)


class Cammed(Rig):
    """m1 on spring k1 (pushed by F), m2 on spring k2, s2 = a*s1 + b*s1^2.
    ``m2_first`` declares m2 first: the dummy derivatives then fall on m1,
    whose position must be found from the constraint by IDAS (nonlinear)."""

    def __init__(self, m2_first=False, s2=S2, v2=V2, **kw):
        self._m2_first, self._s2, self._v2 = m2_first, s2, v2
        super().__init__(**kw)

    def declare(self):
        make = [lambda: setattr(self, "m1", Mass(m=M1, s0=S1, v0=V1)),
                lambda: setattr(self, "m2", Mass(m=M2, s0=self._s2, v0=self._v2))]
        for f in (make[::-1] if self._m2_first else make):
            f()
        self.k1 = Spring(k=K1)
        self.k2 = Spring(k=K2)
        self.push = Force(F=F)
        self.cam = Cam(a=A, b=B)
        self.frame = Fixed()
        self.connect(self.frame.flange, self.k1.flange_a, self.k2.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a, self.push.flange)
        self.connect(self.m1.flange_b, self.cam.flange_a)
        self.connect(self.cam.flange_b, self.m2.flange_a)
        self.connect(self.m2.flange_b, self.k2.flange_b)


def by_hand(t):
    """(m1 + m2 g'^2) q'' + m2 g' g'' q'^2 = F - k1 q - k2 g g', g = a q + b q^2."""
    def rhs(_, y):
        q, w = y
        g, dg = A * q + B * q * q, A + 2 * B * q
        return [w, (F - K1 * q - K2 * g * dg - M2 * dg * 2 * B * w * w) / (M1 + M2 * dg * dg)]
    sol = solve_ivp(rhs, (0.0, t[-1]), [S1, V1], t_eval=t, method="DOP853",
                    rtol=1e-13, atol=1e-15)
    q, w = sol.y
    return q, w, A * q + B * q * q, (A + 2 * B * q) * w


def energy(r):
    return (0.5 * M1 * r["m1.v"] ** 2 + 0.5 * M2 * r["m2.v"] ** 2 + 0.5 * K1 * r["m1.s"] ** 2
            + 0.5 * K2 * r["m2.s"] ** 2 - F * r["m1.s"])


@pytest.mark.parametrize("m2_first", [False, True], ids=["ode", "idas"])
def test_cam_between_two_masses_follows_the_hand_reduced_ode(m2_first):
    rig = Cammed(m2_first=m2_first)
    dae = rig.compile()
    # two of the four states remain: the dummy derivatives fall on the later-declared mass
    kept, gone = ("m1", "m2") if not m2_first else ("m2", "m1")
    assert dae.x_names == [f"{kept}.s", f"{kept}.v"]
    assert dae.is_ode != m2_first            # solved symbolically, or by IDAS from the constraint
    if m2_first:
        assert f"{gone}.s" in dae.z_names
    r = rig.simulate(2.0, n_out=401, **TIGHT)
    q, w, s2, v2 = by_hand(r.t)
    assert np.ptp(q) > 0.05                  # it moves: a real test
    for got, want in ((r["m1.s"], q), (r["m1.v"], w), (r["m2.s"], s2), (r["m2.v"], v2)):
        assert np.max(np.abs(got - want)) < 1e-6 * np.max(np.abs(want))
    # the constraint and its derivative hold along the solution (no drift)
    assert np.max(np.abs(r["m2.s"] - A * r["m1.s"] - B * r["m1.s"] ** 2)) < 1e-9
    assert np.max(np.abs(r["m2.v"] - (A + 2 * B * r["m1.s"]) * r["m1.v"])) < 1e-8
    # conservative: springs, a constant force and an ideal cam
    e = energy(r)
    assert np.max(np.abs(e - e[0])) < 1e-7 * abs(e[0])


A1, B1, A2, B2 = 0.8, 0.5, 1.2, -0.3


def two_cams(q):
    """g = g2(g1(q)) and its first two derivatives."""
    g1, d1 = A1 * q + B1 * q * q, A1 + 2 * B1 * q
    return (A2 * g1 + B2 * g1 * g1, (A2 + 2 * B2 * g1) * d1,
            2 * B2 * d1 * d1 + (A2 + 2 * B2 * g1) * 2 * B1)


class TwoCams(Rig):
    """Two cams in series through a massless joint: the joint's position is
    algebraic, so index reduction needs its first and second derivatives as
    new unknowns (both become dummy derivatives)."""

    def declare(self):
        g, dg, _ = two_cams(S1)
        self.m1 = Mass(m=M1, s0=S1, v0=V1)
        self.m2 = Mass(m=M2, s0=g, v0=dg * V1)
        self.k1 = Spring(k=K1)
        self.k2 = Spring(k=K2)
        self.c1 = Cam(a=A1, b=B1)
        self.c2 = Cam(a=A2, b=B2)
        self.frame = Fixed()
        self.connect(self.frame.flange, self.k1.flange_a, self.k2.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.c1.flange_a)
        self.connect(self.c1.flange_b, self.c2.flange_a)
        self.connect(self.c2.flange_b, self.m2.flange_a)
        self.connect(self.m2.flange_b, self.k2.flange_b)


def test_two_cams_through_a_massless_joint_need_its_second_derivative():
    rig = TwoCams()
    assert rig.compile().x_names == ["m1.s", "m1.v"]
    r = rig.simulate(2.0, n_out=201, **TIGHT)

    def rhs(_, y):
        q, w = y
        g, dg, ddg = two_cams(q)
        return [w, (-K1 * q - K2 * g * dg - M2 * dg * ddg * w * w) / (M1 + M2 * dg * dg)]
    q = solve_ivp(rhs, (0.0, 2.0), [S1, V1], t_eval=r.t, method="DOP853",
                  rtol=1e-13, atol=1e-15).y[0]
    assert np.ptp(q) > 0.1
    assert np.max(np.abs(r["m1.s"] - q)) < 1e-6 * np.max(np.abs(q))
    assert np.max(np.abs(r["m2.s"] - two_cams(q)[0])) < 1e-6 * np.max(np.abs(q))
    assert np.max(np.abs(r["c1.flange_b.s"] - A1 * q - B1 * q * q)) < 1e-6 * np.max(np.abs(q))


def test_the_reduced_rig_runs_compiled_as_it_runs_in_casadi():
    a = Cammed().simulate(1.0, n_out=101, **TIGHT)
    b = Cammed().simulate(1.0, n_out=101, backend="c", **TIGHT)
    for name in ("m1.s", "m2.s", "m2.v", "cam.flange_a.f"):
        assert np.max(np.abs(a[name] - b[name])) < 1e-8 * np.max(np.abs(a[name]))


def test_cam_forces_do_equal_and_opposite_power():
    r = Cammed().simulate(1.0, n_out=201, **TIGHT)
    p_a = r["cam.flange_a.f"] * r["m1.v"]
    p_b = r["cam.flange_b.f"] * r["m2.v"]
    assert np.max(np.abs(p_a)) > 0.1
    assert np.max(np.abs(p_a + p_b)) < 1e-9 * np.max(np.abs(p_a))


def test_a_start_that_violates_the_constraint_is_refused():
    with pytest.raises(ModelError) as e:
        Cammed(s2=S2 + 0.01).compile()
    msg = str(e.value)
    assert "m2.s" in msg and "constraint" in msg and "\n" not in msg


def test_a_cam_at_its_dead_point_is_refused_in_one_line():
    """A mass held by a cam on the frame: s_frame = b*s^2, started at s = 0,
    where a + 2*b*s = 0: the constraint cannot be solved for the mass."""
    class Dead(Rig):
        def declare(self):
            self.m = Mass(m=1.0)
            self.k = Spring(k=10.0)
            self.cam = Cam(a=0.0, b=1.0)
            self.frame = Fixed()
            self.connect(self.frame.flange, self.k.flange_a, self.cam.flange_b)
            self.connect(self.k.flange_b, self.m.flange_a)
            self.connect(self.m.flange_b, self.cam.flange_a)
    with pytest.raises(ModelError) as e:
        Dead().compile()
    msg = str(e.value)
    assert "numerically singular" in msg and "cam (Cam), equation 1" in msg
    assert "\n" not in msg
