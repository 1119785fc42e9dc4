"""Index reduction to any index (Pantelides' algorithm, dummy derivatives)
against physics: two masses on springs tied by a nonlinear cam,
s2 = a*s1 + b*s1^2 (index 3: a constraint on positions), against the ODE
reduced by hand (Lagrange's equation in s1) integrated by scipy; the
constraint along the solution; energy; and the refusals."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdbfs.components import Cam, Fixed, Force, Mass, Spring
from pdbfs.components.hydraulic import Piston, Volume
from pdbfs.errors import ModelError, ParameterError
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


# -- a cam, a massless piston and an incompressible line (issue 21) ------------------------
AP1, AP2, M3 = 2e-3, 1e-3, 0.3       # piston areas (m2), a mass on the driven piston (kg)
RATIO = AP1 / AP2                    # the line's velocity ratio
G0, DG0 = A * S1 + B * S1 ** 2, A + 2 * B * S1
S2L = 0.02                           # m2's start (the line ties velocities, not positions)


class CamLine(Rig):
    """m1 on k1 drives a cam; the cam drives piston p1 (massless, or carrying
    m3), whose oil, incompressible, drives piston p2 carrying m2 on k2; with
    ``lever`` a rigid lever of ratio -A1/A2 replaces pistons and line. One
    degree of freedom; the velocity of m2 follows from the line's balance
    A1*v1 + A2*v2 = 0, which alias elimination turns into a scaled alias."""

    def __init__(self, m3=False, lever=False, v2=-RATIO * DG0 * V1, **kw):
        self._m3, self._lever, self._v2 = m3, lever, v2
        super().__init__(**kw)

    def declare(self):
        self.m1 = Mass(m=M1, s0=S1, v0=V1)
        self.k1 = Spring(k=K1)
        self.cam = Cam(a=A, b=B)
        self.m2 = Mass(m=M2, s0=-RATIO * G0 if self._lever else S2L, v0=self._v2)
        self.k2 = Spring(k=K2)
        self.frame = Fixed()
        self.connect(self.frame.flange, self.k1.flange_a, self.k2.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.cam.flange_a)
        if self._lever:
            self.lever = Cam(a=-RATIO, b=0.0)
            self.connect(self.cam.flange_b, self.lever.flange_a)
            self.connect(self.lever.flange_b, self.m2.flange_a)
        else:
            self.p1, self.p2 = Piston(A=AP1), Piston(A=AP2)
            if self._m3:
                self.m3 = Mass(m=M3, s0=G0, v0=DG0 * V1)
                self.connect(self.cam.flange_b, self.m3.flange_a)
                self.connect(self.m3.flange_b, self.p1.flange)
            else:
                self.connect(self.cam.flange_b, self.p1.flange)
            self.connect(self.p1.port, self.p2.port)
            self.connect(self.p2.flange, self.m2.flange_a)
        self.connect(self.m2.flange_b, self.k2.flange_b)


def line_by_hand(t, m3, s2_start):
    """Lagrange's equation in q = m1.s, with s2 = s2_start - R*(g(q) - g(S1)):
    (M1 + mj g'^2) q'' + mj g' g'' q'^2 = -K1 q + K2 s2 R g', mj = M2 R^2 (+ M3)."""
    mj = M2 * RATIO ** 2 + (M3 if m3 else 0.0)

    def rhs(_, y):
        q, w = y
        g, dg = A * q + B * q * q, A + 2 * B * q
        s2 = s2_start - RATIO * (g - G0)
        return [w, (-K1 * q + K2 * s2 * RATIO * dg - mj * dg * 2 * B * w * w) / (M1 + mj * dg * dg)]
    q, w = solve_ivp(rhs, (0.0, t[-1]), [S1, V1], t_eval=t, method="DOP853",
                     rtol=1e-13, atol=1e-15).y
    return q, w, s2_start - RATIO * (A * q + B * q * q - G0)


@pytest.mark.parametrize("kw", [{}, {"m3": True}, {"lever": True}],
                         ids=["massless-piston", "mass-on-driven-piston", "rigid-lever"])
def test_a_cam_through_an_incompressible_line_follows_the_hand_reduced_ode(kw):
    rig = CamLine(**kw)
    assert rig.compile().x_names[:2] == ["m1.s", "m1.v"]
    r = rig.simulate(1.0, n_out=201, **TIGHT)
    s2_start = -RATIO * G0 if kw.get("lever") else S2L
    q, w, s2 = line_by_hand(r.t, kw.get("m3", False), s2_start)
    assert np.ptp(q) > 0.05
    assert np.max(np.abs(r["m1.s"] - q)) < 1e-9 * np.max(np.abs(q))
    assert np.max(np.abs(r["m1.v"] - w)) < 1e-9 * np.max(np.abs(w))
    assert np.max(np.abs(r["m2.s"] - s2)) < 1e-9 * np.max(np.abs(s2))
    v2 = -RATIO * (A + 2 * B * r["m1.s"]) * r["m1.v"]
    assert np.max(np.abs(r["m2.v"] - v2)) < 1e-8 * np.max(np.abs(v2))
    if not kw.get("lever"):                  # the massless piston sits where the cam puts it
        x1 = A * r["m1.s"] + B * r["m1.s"] ** 2
        assert np.max(np.abs(r["p1.flange.s"] - x1)) < 1e-10
    e = 0.5 * M1 * r["m1.v"] ** 2 + 0.5 * M2 * r["m2.v"] ** 2 + 0.5 * K1 * r["m1.s"] ** 2 \
        + 0.5 * K2 * r["m2.s"] ** 2 + (0.5 * M3 * r["m3.v"] ** 2 if kw.get("m3") else 0.0)
    assert np.max(np.abs(e - e[0])) < 1e-9 * e[0]


class CamVolume(Rig):
    """A cam drives a massless piston into a sealed chamber: the piston's
    position has no declared start; it is where the cam puts it."""

    def declare(self):
        self.m1 = Mass(m=M1, s0=S1, v0=V1)
        self.k1 = Spring(k=K1)
        self.cam = Cam(a=A, b=B)
        self.p1 = Piston(A=AP1)
        self.oil = Volume(V=1e-3, K=1e6, p0=0.0, cavitation=False)
        self.frame = Fixed()
        self.connect(self.frame.flange, self.k1.flange_a)
        self.connect(self.k1.flange_b, self.m1.flange_a)
        self.connect(self.m1.flange_b, self.cam.flange_a)
        self.connect(self.cam.flange_b, self.p1.flange)
        self.connect(self.p1.port, self.oil.port)


def test_a_position_with_no_declared_start_is_solved_for_not_checked():
    r = CamVolume().simulate(1.0, n_out=201, **TIGHT)
    c = 1e6 * AP1 / 1e-3                     # oil pressure per metre of stroke, K*A/V

    def rhs(_, y):                           # M1 q'' = -K1 q - p A g', p = c (g(q) - g(S1))
        q, w = y
        g, dg = A * q + B * q * q, A + 2 * B * q
        return [w, (-K1 * q - c * (g - G0) * AP1 * dg) / M1]
    q = solve_ivp(rhs, (0.0, 1.0), [S1, V1], t_eval=r.t, method="DOP853",
                  rtol=1e-13, atol=1e-15).y[0]
    assert r["p1.flange.s"][0] == pytest.approx(G0, rel=1e-12)
    assert np.ptp(q) > 0.02
    assert np.max(np.abs(r["m1.s"] - q)) < 1e-9 * np.max(np.abs(q))
    assert np.max(np.abs(r["oil.p"] - c * (A * q + B * q * q - G0))) < 1e-8 * np.max(r["oil.p"])


def test_a_set_start_of_a_state_made_algebraic_is_refused_not_ignored():
    rig = CamLine()
    assert "m2.v" not in rig.compile().x_names          # the line computes it
    for kw in ({"params": {"m2.v0": 1.0}}, {"params": {"m1.v0": 2 * V1}},
               {"start": {"m2.v": 1.0}}):
        with pytest.raises(ParameterError) as e:
            rig.simulate(0.1, **kw)
        msg = str(e.value)
        assert "m2.v" in msg and "cam (Cam), equation 1" in msg and "\n" not in msg
    # consistent starts are taken as given
    r = rig.simulate(0.1, params={"m1.v0": 2 * V1, "m2.v0": -RATIO * DG0 * 2 * V1})
    assert r["m2.v"][0] == pytest.approx(-RATIO * DG0 * 2 * V1, rel=1e-12)


def test_a_sweep_point_whose_start_the_constraint_overrides_is_reported_not_run():
    """Also in worker processes (the DAE's record of reduced starts travels)."""
    import pdbfs
    res = pdbfs.sweep(CamLine(), {"m1.v0": [V1, 2 * V1]}, t_end=0.05, workers=2)
    assert res[0].error is None
    assert res[1].error_type == "ParameterError" and "m2.v" in res[1].error
