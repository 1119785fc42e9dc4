"""Bad input gets a clear error naming the culprit."""
import math

import pytest

import pdbfs
from pdbfs import ConnectError, ModelError, ParameterError, SolverError
from pdbfs.cli import main
from pdbfs.components import Fixed, Force, Mass, PositionSensor, Spring
from pdbfs.models import paper_rig
from pdbfs import Variable, eq


@pytest.mark.parametrize("value, msg", [(0.0, "must be > 0"), (-3.0, "must be > 0"),
                                        (math.nan, "must be finite"),
                                        (math.inf, "must be finite"), ("heavy", "not a number")])
def test_bad_mass_at_construction(value, msg):
    with pytest.raises(ParameterError, match=f"Mass.m .*{msg}"):
        Mass(m=value)


@pytest.mark.parametrize("name, value, msg", [
    ("hammer.m", 0.0, "hammer.m = 0 kg: must be > 0"),
    ("oil.k", -1.0, "oil.k = -1 N/m: must be > 0"),
    ("contact.k", math.nan, "contact.k = nan: must be finite"),
    ("seal.c", math.inf, "seal.c = inf: must be finite"),
    ("oil.n", 0.5, "oil.n = 0.5: must be >= 1"),
])
def test_bad_parameter_values_per_call(name, value, msg):
    with pytest.raises(ParameterError, match=msg.replace("(", r"\(")):
        paper_rig().simulate(params={name: value})


def test_unknown_parameter_suggests_names():
    with pytest.raises(ParameterError, match="unknown parameter 'hamer.v0'.*hammer.v0"):
        paper_rig().simulate(params={"hamer.v0": 3.0})
    with pytest.raises(ParameterError, match="Mass: unknown parameter.*mass.*it has: m, s0, v0"):
        Mass(mass=3.0)


def test_cli_reports_unknown_parameter_and_exits_nonzero(capsys, tmp_path):
    assert main(["simulate", "--set", "hammer.vv=3", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "unknown parameter 'hammer.vv'" in err and "Traceback" not in err
    assert main(["simulate", "--set", "hammer.v0", "--out", str(tmp_path)]) == 2
    assert "expected NAME=VALUE" in capsys.readouterr().err
    assert main(["simulate", "--set", "hammer.m=-2", "--out", str(tmp_path)]) == 2
    assert "hammer.m = -2 kg: must be > 0" in capsys.readouterr().err
    assert main(["simulate", "--rig", "nope", "--out", str(tmp_path)]) == 2
    assert "unknown rig 'nope'" in capsys.readouterr().err


def test_flange_connected_to_itself():
    class R(pdbfs.Rig):
        def declare(self):
            self.m = Mass()
            self.connect(self.m.flange_a, self.m.flange_a)
    with pytest.raises(ConnectError, match="m.flange_a is connected to itself"):
        R()


def test_incompatible_connectors():
    class R(pdbfs.Rig):
        def declare(self):
            self.m = Mass()
            self.sensor = PositionSensor()
            self.connect(self.m.flange_a, self.sensor.s)
    with pytest.raises(ConnectError, match=r"incompatible connectors: m.flange_a \(Flange\), "
                                           r"sensor.s \(SignalOutput\)"):
        R()


def test_connecting_a_component_instead_of_a_flange():
    class R(pdbfs.Rig):
        def declare(self):
            self.m = Mass()
            self.k = Spring()
            self.connect(self.m, self.k.flange_a)
    with pytest.raises(ConnectError, match="is not a connector"):
        R()


class Leaky(Mass):
    """A broken mass: forgets the equation of its acceleration."""

    def equations(self):
        return super().equations()[:-1]


def test_component_missing_an_equation_is_named():
    class R(pdbfs.Rig):
        def declare(self):
            self.body = Leaky()
    with pytest.raises(ModelError, match=r"component body \(Leaky\) is under-determined: "
                                         r"4 equations for 5 unknowns"):
        R().compile()


class Idle(pdbfs.Component):
    """Balanced by count, but its equation determines nothing."""

    def declare(self):
        self.x = Variable("m", "a variable nothing determines")

    def equations(self):
        return [eq(self.x, self.x)]


def test_under_determined_rig_names_the_variable():
    class R(pdbfs.Rig):
        def declare(self):
            self.idle = Idle()
            self.m = Mass()
    with pytest.raises(ModelError, match="under-determined: no equation determines idle.x"):
        R().compile()


def test_over_determined_rig_names_the_equation():
    class R(pdbfs.Rig):
        def declare(self):
            self.a = Fixed(s0=0.0)
            self.b = Fixed(s0=0.1)
            self.connect(self.a.flange, self.b.flange)
    with pytest.raises(ModelError, match=r"over-determined: connect\(a.flange, b.flange\)"):
        R().compile()


def test_solver_failure_reports_time_and_cause():
    class R(pdbfs.Rig):
        def declare(self):
            self.m = Mass(m=1.0)
            self.f = Force(function=lambda t: 1.0 / (0.001 - t) ** 3)   # blows up at 1 ms
            self.connect(self.m.flange_a, self.f.flange)
    with pytest.raises(SolverError, match=r"failed after t = 0.00099\d* s .*too many steps"):
        R().simulate(0.002, n_out=2001, backend="casadi")
    # the default, the compiled explicit method: its step shrinks to nothing at the singularity
    with pytest.raises(SolverError, match=r"failed after t = 0.00(1|099\d*) s .*error test failed "
                                          r".*step size fell below roundoff"):
        R().simulate(0.002, n_out=2001)


def test_bad_solver_settings():
    rig = paper_rig()
    with pytest.raises(ParameterError, match="rtol"):
        rig.simulate(rtol=-1.0)
    with pytest.raises(ParameterError, match="unknown method 'rk4'"):
        rig.simulate(method="rk4")
    with pytest.raises(ParameterError, match="t_end"):
        rig.simulate(t_end=math.nan)
    with pytest.raises(ParameterError, match="not a state"):
        rig.simulate(start={"hammer.x": 1.0})


def test_rigid_bodies_with_inconsistent_start_are_named():
    class R(pdbfs.Rig):
        def declare(self):
            self.a = Mass(v0=1.0)
            self.b = Mass(v0=0.0)
            self.connect(self.a.flange_b, self.b.flange_a)
    with pytest.raises(ModelError, match=r"b.v starts at 0 m/s.*consistent start values"):
        R().compile()


def test_fmu_export_of_a_dae_rig_is_a_clear_error(tmp_path):
    from test_core import Chain
    with pytest.raises(pdbfs.ExportError, match="algebraic variable.*k0.s_rel"):
        Chain(2).export_fmu(tmp_path / "x.fmu")
    assert not (tmp_path / "x.fmu").exists()


def test_equation_using_a_symbol_of_another_rig_is_named():
    other = Mass()

    class Sneaky(pdbfs.Component):
        def declare(self):
            self.x = Variable("m", "copies a foreign position")

        def equations(self):
            return [eq(self.x, other.s)]

    class R(pdbfs.Rig):
        def declare(self):
            self.sneaky = Sneaky()
    with pytest.raises(ModelError, match=r"sneaky \(Sneaky\), equation 1: uses s, which belong"):
        R().compile()
