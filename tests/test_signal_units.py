"""Signals join in one unit: connect() refuses an Input in Pa wired to a
SignalForce's u in N (export-ssp's rule: "" and "1" alike), a block with a
gain converts (input_unit), and a parameter is a number (Gain(k="2") is
refused at construction); dimensionless values are shown bare."""
import pytest

import pdbfs
from pdbfs.components import Mass, SignalForce
from pdbfs.components import blocks as B
from pdbfs.modelling import SignalInput, SignalOutput, quantity


class Pushed(pdbfs.Rig):
    """A free mass pushed by ``source``'s signal, through ``via`` if given."""

    def __init__(self, source, via=None, **kw):
        self._source, self._via = source, via
        super().__init__(**kw)

    def declare(self):
        self.body = Mass(m=2.0)
        self.push = SignalForce()
        self.force = self._source
        self.connect(self.body.flange_b, self.push.flange)
        if self._via is None:
            self.connect(self.force.y, self.push.u)
            return
        self.via = self._via
        self.connect(self.force.y, self.via.u)
        self.connect(self.via.y, self.push.u)


def test_an_input_in_pa_on_a_force_is_refused_at_connect():
    with pytest.raises(pdbfs.ConnectError) as err:
        Pushed(B.Input("Pa"))
    assert str(err.value) == ("connect(): signals of different units: force.y in Pa, push.u in "
                              "N; join signals of one unit (a Gain with unit= and input_unit= "
                              "converts)")
    with pytest.raises(pdbfs.ConnectError, match="force.y in 1, push.u in N"):
        Pushed(B.Input())                        # a plain number is no force either


def test_a_gain_converts_and_one_without_input_unit_does_not():
    area = 2e-4
    rig = Pushed(B.Input("Pa", start=1e5), B.Gain(unit="N", input_unit="Pa", k=area))
    res = rig.simulate(0.1, n_out=11)
    assert res["push.force"][-1] == pytest.approx(1e5 * area, rel=1e-12)
    with pytest.raises(pdbfs.ConnectError, match="force.y in Pa, via.u in N"):
        Pushed(B.Input("Pa"), B.Gain(unit="N"))
    with pytest.raises(pdbfs.ParameterError, match="Limiter: takes its input in the unit of its "
                       "output"):
        B.Limiter(unit="N", input_unit="Pa")


def test_one_and_none_are_the_same_unit():
    class Plain(pdbfs.Component):
        def declare(self):
            self.y = SignalOutput("", "A number")

        def equations(self):
            return [self.y.value - 1.0]

    class Takes(pdbfs.Component):
        def declare(self):
            self.u = SignalInput("1", "A number")

    class Rig(pdbfs.Rig):
        def declare(self):
            self.a, self.b = Plain(), Takes()
            self.connect(self.a.y, self.b.u)

    Rig().compile()


@pytest.mark.parametrize("value", ["2", True, None, [2.0]])
def test_a_parameter_that_is_no_number_is_refused_at_construction(value):
    with pytest.raises(pdbfs.ParameterError) as err:
        B.Gain(k=value)
    assert str(err.value).startswith(f"Gain.k = {value!r}: not a number" if isinstance(value, str)
                                     else "Gain.k = ")
    assert "not a number (Gain (unit of y per unit of u));" in str(err.value)


def test_dimensionless_values_are_shown_without_a_unit():
    assert quantity(0.5, "1") == "0.5" and quantity(0.5, "") == "0.5"
    assert quantity(0.5, "m") == "0.5 m"
    with pytest.raises(pdbfs.ParameterError, match=r"Gain.k = nan: must be finite \(Gain \(unit "
                       r"of y per unit of u\)\)$"):
        B.Gain(k=float("nan"))
    with pytest.raises(pdbfs.ParameterError, match=r"^PID.Nd = -1: must be > 0 \(Derivative"):
        B.PID(kind="PD", Nd=-1.0)


class Loop(pdbfs.Rig):
    """A mass pushed by y = 1 + k2 y (an algebraic loop through an Add)."""

    def __init__(self, k2=1.0, **kw):
        self._k2 = k2
        super().__init__(**kw)

    def declare(self):
        self.one = B.Constant(k=1.0, unit="N")
        self.add = B.Add(unit="N", k2=self._k2)
        self.push = SignalForce()
        self.body = Mass(m=1.0)
        self.connect(self.one.y, self.add.u1)
        self.connect(self.add.y, self.add.u2, self.push.u)
        self.connect(self.body.flange_b, self.push.flange)


def test_a_singular_algebraic_loop_is_refused_before_the_run():
    """y = 1 + y has no solution: it was run and reported as a NaN "check a
    stiffness or exponent"; y = 1 + y/2 is y = 2."""
    with pytest.raises(pdbfs.ParameterError) as err:
        Loop().simulate(0.1)
    assert str(err.value).startswith("add (Add), equation 1: the algebraic loop through it has "
                                     "no unique solution") and "add.k2 = 1" in str(err.value)
    assert Loop(0.5).simulate(0.1)["push.force"][-1] == pytest.approx(2.0, rel=1e-12)
    with pytest.raises(pdbfs.ParameterError, match="no unique solution"):
        Loop(0.5).simulate(0.1, params={"add.k2": 1.0})
