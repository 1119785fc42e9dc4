"""The acausal core: composition, simplification, the IDAS path, results."""
import numpy as np
import pytest

import pdbfs
from pdbfs import Parameter, eq
from pdbfs.components import (Damper, Fixed, Force, ForceSensor, Gravity, Mass,
                              PartialCompliant, PositionSensor, PressureSensor, SealFriction,
                              SpeedSensor, Spring)
from pdbfs.models import paper_rig

TIGHT = dict(rtol=1e-10, atol=1e-13)


class HardeningSpring(PartialCompliant):
    """f = k*(e + b*e^3): a nonlinear spring that is never singular."""

    k = Parameter(1.0, "N/m", "Linear stiffness", positive=True)
    b = Parameter(0.0, "1/m2", "Cubic hardening", min=0.0)

    def equations(self):
        return super().equations() + [eq(self.f, self.k * (self.s_rel + self.b * self.s_rel ** 3))]


class Chain(pdbfs.Rig):
    """frame - n hardening springs in series - body."""

    def __init__(self, n, **kw):
        self._n = n
        super().__init__(**kw)

    def declare(self):
        self.frame = Fixed()
        self.body = Mass(m=1.0, v0=2.0)
        prev = self.frame.flange
        for i in range(self._n):
            k = 1000.0 * self._n            # n springs of n*k in series act like k
            spring = HardeningSpring(k=k, b=50.0 * self._n ** 2)
            setattr(self, f"k{i}", spring)
            self.connect(prev, spring.flange_a)
            prev = spring.flange_b
        self.connect(prev, self.body.flange_a)


def test_nonlinear_algebraic_loop_goes_to_idas():
    two, one = Chain(2), Chain(1)
    dae = two.compile()
    assert dae.z.numel() > 0 and not dae.is_ode       # the node position is implicit
    assert one.compile().is_ode
    r2 = two.simulate(0.5, n_out=201, **TIGHT)
    r1 = one.simulate(0.5, n_out=201, **TIGHT)
    assert np.max(np.abs(r2["body.s"] - r1["body.s"])) < 1e-7 * np.max(np.abs(r1["body.s"]))
    # energy of the conservative chain: kinetic + sum of spring energies
    def pe(res, n):
        return sum(1000.0 * n * (0.5 * res[f"k{i}.s_rel"] ** 2
                                 + 50.0 * n ** 2 * res[f"k{i}.s_rel"] ** 4 / 4) for i in range(n))
    E = 0.5 * r2["body.v"] ** 2 + pe(r2, 2)
    assert np.max(np.abs(E - 2.0)) < 1e-6
    # IDAS starts consistently whatever the horizon and grid
    for t_end, n in ((0.1, 11), (0.01, 3)):
        short = two.simulate(t_end, n_out=n, **TIGHT)
        assert np.allclose(short["body.s"], one.simulate(t_end, n_out=n, **TIGHT)["body.s"],
                           rtol=1e-6, atol=1e-9)
    assert two.simulate(0.5, n_out=51).peak("body.s")[1] == pytest.approx(
        r1.peak("body.s")[1], rel=1e-6)


class Drop(pdbfs.Rig):
    """A body falling under gravity, watched by sensors."""

    def declare(self):
        self.body = Mass(m=3.0)
        self.weight = Gravity(m=self.body.m)
        self.pos = PositionSensor()
        self.speed = SpeedSensor()
        self.connect(self.body.flange_a, self.weight.flange, self.pos.flange, self.speed.flange)


def test_free_fall_with_sensors_and_bound_parameter():
    rig = Drop()
    dae = rig.compile()
    assert "weight.m" not in dae.p_names      # bound to body.m, not a free parameter
    res = rig.simulate(1.0, n_out=11, params={"body.m": 5.0})
    g = 9.80665
    assert np.allclose(res["pos.s"], 0.5 * g * res.t ** 2, rtol=1e-9, atol=1e-12)
    assert np.allclose(res["speed.v"], g * res.t, rtol=1e-9, atol=1e-12)
    assert np.allclose(res["body.flange_a.f"], 5.0 * g)      # the weight acts on the body


class Bench(pdbfs.Rig):
    """A body on a spring pushed through force and pressure sensors by a ramp."""

    def declare(self):
        self.frame = Fixed()
        self.spring = Spring(k=1e4)
        self.damper = Damper(c=50.0)
        self.seal = SealFriction(c=0.0, F_c=5.0, v_eps=1e-4)
        self.body = Mass(m=2.0)
        self.load = ForceSensor()
        self.gauge = PressureSensor(A=1e-3)
        self.push = Force(function=lambda t: 100.0 * t)
        self.connect(self.frame.flange, self.spring.flange_a, self.damper.flange_a,
                     self.seal.flange_a)
        self.connect(self.spring.flange_b, self.damper.flange_b, self.seal.flange_b,
                     self.body.flange_a)
        self.connect(self.body.flange_b, self.load.flange_a)
        self.connect(self.load.flange_b, self.gauge.flange_a)
        self.connect(self.gauge.flange_b, self.push.flange)


def test_sensors_pass_the_force_through():
    res = Bench().simulate(0.5, n_out=51, **TIGHT)
    assert np.allclose(res["push.force"], 100.0 * res.t)
    # the force pulling the body down puts both sensors in tension
    assert np.allclose(res["load.f"], res["push.force"], atol=1e-9)
    assert np.allclose(res["gauge.p"] * 1e-3, -res["load.f"], atol=1e-9)
    # Newton on the body: m a = push - spring - damper - Coulomb friction
    a = res["body.a"]
    rhs = (res["push.force"] - 1e4 * res["body.s"] - 50.0 * res["body.v"]
           - 5.0 * np.tanh(res["body.v"] / 1e-4))
    assert np.allclose(2.0 * a, rhs, atol=1e-6)


class Sub(pdbfs.Rig):
    """A rig with flanges of its own, used as a component: two springs in
    parallel around a mass."""

    def declare(self):
        from pdbfs import Flange
        self.flange_a = Flange()
        self.flange_b = Flange()
        self.s1 = Spring(k=100.0)
        self.s2 = Spring(k=300.0)
        self.connect(self.flange_a, self.s1.flange_a, self.s2.flange_a)
        self.connect(self.flange_b, self.s1.flange_b, self.s2.flange_b)


def test_rig_used_as_component():
    class Outer(pdbfs.Rig):
        def declare(self):
            self.frame = Fixed()
            self.springs = Sub()
            self.body = Mass(m=1.0, v0=1.0)
            self.connect(self.frame.flange, self.springs.flange_a)
            self.connect(self.springs.flange_b, self.body.flange_a)
    res = Outer().simulate(1.0, n_out=101, **TIGHT)
    w = np.sqrt(400.0)
    assert np.allclose(res["body.s"], np.sin(w * res.t) / w, atol=1e-8)
    assert np.allclose(res["springs.s2.f"], 3 * res["springs.s1.f"], atol=1e-8)
    assert "springs.s1.k" in Outer().compile().p_names


def test_dotted_names_reach_everything():
    dae = paper_rig().compile()
    for name in ("hammer.m", "contact.k", "oil.A", "seal.c", "mount.k"):
        assert name in dae.p_names
    for name in ("oil.pressure", "contact.fc", "hammer.s", "piston.v", "breech.a",
                 "contact.hertz.fc", "contact.damping.fc", "seal.f", "mount.f"):
        assert name in dae.y_names
    units = {v.name: v.unit for v in dae.y_info}
    assert units["oil.pressure"] == "Pa" and units["contact.fc"] == "N"
    assert all(p.unit and p.description for p in dae.params)


def test_paper_rig_simplifies_to_six_states_and_no_algebraic():
    dae = paper_rig().compile()
    assert dae.x_names == ["hammer.s", "hammer.v", "piston.s", "piston.v", "breech.s",
                           "breech.v"]
    assert dae.is_ode
    # the ODE depends only on states, parameters: no derivative symbols left
    names = {s.name() for s in __import__("casadi").symvar(dae.ode)}
    assert not any(n.startswith("der(") for n in names)


def test_parameters_change_without_rebuilding(monkeypatch):
    rig = paper_rig()
    dae = rig.compile()
    import pdbfs.modelling.flatten as F
    import pdbfs.modelling.structure as S

    def boom(*a, **k):
        raise AssertionError("rebuilt")
    monkeypatch.setattr(F, "flatten", boom)
    monkeypatch.setattr(S, "simplify", boom)
    r1 = rig.simulate(0.01, params={"hammer.v0": 2.0})
    r2 = rig.simulate(0.01, params={"hammer.v0": 4.0}, rtol=1e-6, n_out=11)
    assert rig.compile() is dae
    assert r2.summary()["peak_pressure"] > r1.summary()["peak_pressure"]


def test_start_values_per_call():
    rig = paper_rig()
    a = rig.simulate(0.01, start={"hammer.v": 4.23})
    b = rig.simulate(0.01, params={"hammer.v0": 4.23})
    assert np.allclose(a["oil.pressure"], b["oil.pressure"])


def test_result_exports(tmp_path):
    import pandas as pd   # a test dependency (pyproject [test])
    res = paper_rig().simulate(0.005, n_out=51)
    df = res.to_pandas(["oil.pressure", "hammer.s"])
    assert isinstance(df, pd.DataFrame) and df.index.name == "time" and len(df) == 51
    assert np.allclose(df["oil.pressure"].to_numpy(), res["oil.pressure"])
    path = res.to_csv(tmp_path / "r.csv")
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    assert data.shape == (51, 1 + len(res.names))
    fig = res.plot(path=tmp_path / "r.png")
    assert (tmp_path / "r.png").stat().st_size > 5000 and len(fig.axes) == 3
    with pytest.raises(KeyError, match="did you mean oil.pressure"):
        res["oil.presure"]


def test_package_functions_stay_callable_after_use():
    """pdbfs.simulate and pdbfs.sweep are functions, whatever was imported."""
    import pdbfs.simulation.run.simulator  # noqa: F401
    import pdbfs.studies.sweeps.sweep  # noqa: F401
    paper_rig().simulate(0.001, n_out=3)
    assert callable(pdbfs.simulate) and callable(pdbfs.sweep)
    assert pdbfs.simulate(paper_rig(), 0.001, n_out=3).t[-1] == 0.001


def test_every_parameter_of_every_rig_has_unit_and_description():
    from pdbfs.models import RIGS
    for name, make in RIGS.items():
        dae = make().compile()
        for p in dae.params:
            assert p.unit and p.description, (name, p.name)
        for _, (_, info) in dae.calculated.items():
            assert info.unit and info.description, (name, info.name)
        for v in dae.y_info:
            assert v.unit and v.description, (name, v.name)


class Lever(pdbfs.Component):
    """An ideal massless lever: flange_b moves ``ratio`` times flange_a."""

    ratio = Parameter(2.0, "1", "Motion ratio s_b / s_a", positive=True)

    def declare(self):
        from pdbfs import Flange
        self.flange_a = Flange()
        self.flange_b = Flange()

    def equations(self):
        return [eq(self.flange_b.s, self.ratio * self.flange_a.s),
                eq(self.flange_a.f + self.ratio * self.flange_b.f, 0.0)]   # no power lost


def test_lever_with_parameter_ratio_reduces_to_one_body():
    """A constraint with a parameter coefficient is still an alias: the second
    body stops being a state and its inertia is seen through ratio^2."""
    class R(pdbfs.Rig):
        def declare(self):
            self.push = Force(F=10.0)
            self.m1 = Mass(m=1.0)
            self.lever = Lever(ratio=3.0)
            self.m2 = Mass(m=0.5)
            self.connect(self.push.flange, self.m1.flange_a)
            self.connect(self.m1.flange_b, self.lever.flange_a)
            self.connect(self.lever.flange_b, self.m2.flange_a)
    rig = R()
    assert rig.compile().x_names == ["m1.s", "m1.v"]
    for r in (3.0, 0.5):
        res = rig.simulate(1.0, n_out=11, params={"lever.ratio": r}, **TIGHT)
        s1 = 10.0 * res.t ** 2 / (2 * (1.0 + r ** 2 * 0.5))
        assert np.allclose(res["m1.s"], s1, rtol=1e-9, atol=1e-12)
        assert np.allclose(res["m2.s"], r * s1, rtol=1e-9, atol=1e-12)
        assert np.allclose(res["lever.flange_b.f"] * 1.0, -0.5 * res["m2.a"], atol=1e-9)


# -- every documented parameter through its constructor (issue 21) -------------------------
def _constructors():
    import inspect
    import pdbfs.components as C
    import pdbfs.components.hydraulic as H
    from pdbfs.modelling import Component
    options = {"Volume": [{"law": law} for law in H.BULK_MODULUS_LAWS],
               "Cylinder": [{"law": law} for law in H.BULK_MODULUS_LAWS],
               "OilColumn": [{}, {"bulk_modulus": True}],
               "HuntCrossleyDamper": [{}] + [{"law": law} for law in C.DAMPING_LAWS],
               "ImpactContact": [{}] + [{"law": law} for law in C.DAMPING_LAWS],
               "ElasticBar": [{"n": 3}]}
    out = []
    for mod in (C, H):
        for name in sorted(dir(mod)):
            cls = getattr(mod, name)
            if inspect.isclass(cls) and issubclass(cls, Component) \
                    and not name.startswith("Partial") and name != "MassChain":   # abstract
                out += [(cls, opts) for opts in options.get(name, [{}])]
    return out


def _another_value(decl, where):
    """A value the declaration allows, other than its default."""
    from pdbfs.errors import ParameterError
    d = float(decl.default)
    for v in (1.5 * d, 0.5 * d, d + 1.0, 0.5, decl.min, decl.max):
        if v is None or v == d:
            continue
        try:
            return decl.check(v, where)
        except ParameterError:
            continue
    raise AssertionError(f"no value other than the default for {where}")


@pytest.mark.parametrize("cls, opts", _constructors(),
                         ids=lambda x: x.__name__ if isinstance(x, type) else
                         ",".join(f"{k}={v}" for k, v in x.items()) or "-")
def test_every_documented_parameter_is_settable_in_the_constructor(cls, opts):
    """Law-specific parameters too (Volume(law="linear", K1=5.0) was refused
    as unknown); a Cylinder's chamber parameters go to its chamber."""
    import casadi as ca
    base = cls(**opts)
    owners = [(base, lambda c: c)]
    if cls.__name__ == "Cylinder":
        owners.append((base.chamber, lambda c: c.chamber))
    checked = set()
    for comp, where in owners:
        for name, slot in comp._params.items():
            if isinstance(slot.value, ca.SX) or (where is not owners[0][1] and name in base._params):
                continue                     # computed from others, or the Cylinder's own
            value = _another_value(slot.decl, f"{cls.__name__}.{name}")
            made = where(cls(**opts, **{name: value}))
            assert made._params[name].value == value, name
            checked.add(name)
    law_own = {"linear": {"K1"}, "air": {"alpha", "n_air", "p_air"}}.get(opts.get("law"), set())
    assert law_own <= checked
    if opts.get("law") in ("hunt-crossley", "flores", "lankarani-nikravesh"):
        assert {"e", "v_impact"} <= checked


def test_a_value_given_for_a_parameter_the_law_computes_is_refused():
    from pdbfs.components import ImpactContact, OilColumn
    from pdbfs.errors import ParameterError
    with pytest.raises(ParameterError, match="OilColumn: k is computed from A, K, L"):
        OilColumn(bulk_modulus=True, k=1e9)
    with pytest.raises(ParameterError, match="ImpactContact: D is computed"):
        ImpactContact(law="flores", D=3.0)
    with pytest.raises(ParameterError, match=r"Volume: K1 belong\(s\) to law='linear'"):
        from pdbfs.components.hydraulic import Volume
        Volume(K1=5.0)                       # the constant law has no K1
