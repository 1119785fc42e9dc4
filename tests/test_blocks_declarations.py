"""The blocks' declarations: every parameter has a unit and a description,
the signals are named as in Modelica.Blocks (input ``u``, output ``y``),
bad constructor arguments and contradicting parameters are refused in one
line naming the culprit, an Input is an input of the rig (not a parameter)
named by its component, and the data a block keeps (a table, a pulse count) reaches
the compiled DAE and its disk cache."""
import inspect

import pytest

import pdbfs
from pdbfs.components import SignalForce, SignalPosition
from pdbfs.components import blocks as B
from pdbfs.components import hydraulic as H
from pdbfs.modelling import SignalInput, SignalOutput


def every_block():
    """One instance of each block class (each PID kind, limited or not)."""
    made = []
    for name in B.__all__:
        cls = getattr(B, name)
        if not inspect.isclass(cls) or cls.__module__ == "pdbfs.components.blocks.interfaces" \
                or name.startswith("Partial"):
            continue
        if cls is B.Table:
            made += [B.Table([0.0, 1.0], [2.0, 3.0]), B.Table([0.0], [1.0], interpolation="hold")]
        elif cls is B.PID:
            made += [B.PID(kind=k, limited=lim) for k in B.PID_KINDS for lim in (False, True)]
        else:
            made.append(cls())
    return made


ACTUATORS = [SignalForce, SignalPosition, H.CommandedValve, H.SignalPressure]


def test_the_library_has_every_block_the_rigs_rely_on():
    names = {type(b).__name__ for b in every_block()}
    assert names >= {"Constant", "Step", "Ramp", "Sine", "Pulse", "Table", "Gain", "Add",
                     "Product", "Limiter", "DeadZone", "Integrator", "FirstOrder", "SecondOrder",
                     "Derivative", "PID", "Input"}
    assert pdbfs.components.SignalForce is SignalForce
    assert pdbfs.components.hydraulic.CommandedValve is H.CommandedValve


@pytest.mark.parametrize("block", every_block() + [cls() for cls in ACTUATORS],
                         ids=lambda b: type(b).__name__)
def test_every_parameter_and_signal_has_a_unit_and_a_description(block):
    for name, slot in block._params.items():
        assert isinstance(slot.decl.unit, str) and slot.decl.unit.strip(), name
        assert isinstance(slot.decl.description, str) and len(slot.decl.description) > 8, name
    for name, c in block._connectors.items():
        if isinstance(c, (SignalInput, SignalOutput)):
            assert c.unit.strip() and c.description.strip(), name


@pytest.mark.parametrize("block", every_block(), ids=lambda b: type(b).__name__)
def test_the_signals_are_u_and_y(block):
    ins = sorted(n for n, c in block._connectors.items() if isinstance(c, SignalInput))
    outs = [n for n, c in block._connectors.items() if isinstance(c, SignalOutput)]
    assert outs == ["y"]
    assert ins in ([], ["u"], ["u1", "u2"])


def test_a_block_takes_the_unit_of_its_signals():
    step = B.Step(unit="N", height=5.0)
    assert step.y.unit == "N"
    assert step._params["height"].decl.unit == "N" and step._params["start_time"].decl.unit == "s"
    limiter = B.Limiter(unit="Pa")
    assert limiter.u.unit == limiter.y.unit == limiter._params["uMax"].decl.unit == "Pa"


@pytest.mark.parametrize("make, culprit", [
    (lambda: B.Step(unit=""), "Step: unit = ''"),
    (lambda: B.Gain(unit=3), "Gain: unit = 3"),
    (lambda: B.Add(n=0), "Add: n = 0 must be a whole number of inputs >= 1"),
    (lambda: B.Product(n=True), "Product: n = True"),
    (lambda: B.Pulse(periods=0), "Pulse: periods = 0 must be a whole number >= 1"),
    (lambda: B.Pulse(periods=2.5), "Pulse: periods = 2.5"),
    (lambda: B.PID(kind="PII"), "PID: kind = 'PII'; choose one of P, PI, PD, PID"),
    (lambda: B.PID(limited="yes"), "PID: limited = 'yes' must be True or False"),
    (lambda: B.PID(kind="P", Ti=1.0), "PID: unknown parameter(s) Ti"),
    (lambda: B.PID(yMax=1.0), "PID: unknown parameter(s) yMax"),
    (lambda: B.FirstOrder(T=0.0), "FirstOrder.T = 0 s: must be > 0"),
    (lambda: B.Input(description=5), "Input: description = 5 must be text"),
    (lambda: B.Input(start="high"), "Input: input start = 'high': must be a number"),
    (lambda: B.Input(start=float("inf")), "Input: input start = inf: must be finite"),
    (lambda: B.Sine(f=float("nan")), "Sine.f = nan: must be finite"),
])
def test_bad_arguments_are_refused_in_one_line(make, culprit):
    with pytest.raises(pdbfs.ParameterError) as err:
        make()
    assert culprit in str(err.value) and "\n" not in str(err.value)


class Pulsed(pdbfs.Rig):
    def declare(self):
        self.src = B.Pulse(periods=3, width=0.2, period=0.5)
        self.control = B.PID(kind="PI", limited=True)
        self.integral = B.Integrator()
        self.connect(self.src.y, self.control.u)
        self.connect(self.control.y, self.integral.u)


@pytest.mark.parametrize("params, culprit", [
    ({"src.width": 0.6}, "src (Pulse): a pulse would be longer than its period "
                         "(src.width = 0.6 s, src.period = 0.5 s)"),
    ({"control.yMin": 2.0}, "control (PID): the upper output limit is below the lower one "
                            "(control.yMin = 2, control.yMax = 1)"),
])
def test_contradicting_parameters_are_refused_naming_them(params, culprit):
    with pytest.raises(pdbfs.ParameterError) as err:
        Pulsed().simulate(1.0, params=params)
    assert str(err.value) == culprit


def test_an_unconnected_block_input_is_refused_naming_it():
    class R(pdbfs.Rig):
        def declare(self):
            self.gain = B.Gain()
            self.integral = B.Integrator()
            self.connect(self.gain.y, self.integral.u)
    with pytest.raises(pdbfs.ConnectError, match="signal input gain.u is not connected"):
        R().compile()


class Commanded(pdbfs.Rig):
    """A sub-rig holding an input, inside a rig holding another."""

    def declare(self):
        self.command = B.Input("N", start=2.0, description="Push")
        self.integral = B.Integrator(unit="N")
        self.connect(self.command.y, self.integral.u)


class Outer(pdbfs.Rig):
    def declare(self):
        self.inner = Commanded()
        self.gain_cmd = B.Input(start=-1.0)
        self.integral = B.Integrator()
        self.connect(self.gain_cmd.y, self.integral.u)


def test_inputs_are_named_by_their_components_and_held_at_their_start():
    rig = Outer()
    inputs = [c for c in rig.walk() if getattr(c, "rig_input", False)]
    assert [c.input_name() for c in inputs] == ["inner.command", "gain_cmd"]
    assert [type(c) for c in inputs] == [B.Input, B.Input]
    dae = rig.compile()
    info = {u.name: u for u in dae.inputs}
    assert list(info) == ["inner.command", "gain_cmd"]
    assert (info["inner.command"].unit, info["inner.command"].start) == ("N", 2.0)
    assert info["gain_cmd"].description.startswith("Input of the rig")
    # inputs are not parameters: no start parameter, nothing to --set
    assert not [n for n in dae.p_names if "command" in n or "gain_cmd" in n]
    res = rig.simulate(1.0, n_out=3, inputs={"inner.command": 5.0})
    assert res["inner.integral.y"][-1] == pytest.approx(5.0, rel=1e-9)
    assert res["integral.y"][-1] == pytest.approx(-1.0, rel=1e-9)     # held at its start
    res = rig.simulate(1.0, n_out=3)
    assert res["inner.integral.y"][-1] == pytest.approx(2.0, rel=1e-9)
    with pytest.raises(pdbfs.ParameterError, match="unknown parameter 'gain_cmd.start'"):
        rig.simulate(1.0, n_out=3, params={"gain_cmd.start": 5.0})


def table_rig(values, periods):
    """A rig of pdbfs's own classes only (its DAE is kept in the disk cache):
    a table and a pulse train, each integrated."""
    rig = pdbfs.Rig()
    rig.table = B.Table([0.0, 0.5], values)
    rig.pulse = B.Pulse(periods=periods, width=0.05, period=0.1)
    rig.integral = B.Integrator()
    rig.pulses = B.Integrator()
    rig.connect(rig.table.y, rig.integral.u)
    rig.connect(rig.pulse.y, rig.pulses.u)
    return rig


def test_the_data_a_block_keeps_reaches_the_compiled_and_cached_dae(monkeypatch, tmp_path):
    """Rigs differing only in a table's values or a pulse count are other
    DAEs, also when read back from the disk cache."""
    from pdbfs.modelling import dae_cache
    from pdbfs.modelling import flatten as flatten_module
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    made = {(v, n): table_rig([1.0, v], n) for v, n in ((2.0, 3), (4.0, 3), (2.0, 5))}
    keys = {k: dae_cache.declaration_key(r) for k, r in made.items()}
    assert None not in keys.values() and len(set(keys.values())) == 3
    want = {(2.0, 3): (1.75, 0.15), (4.0, 3): (3.25, 0.15), (2.0, 5): (1.75, 0.25)}

    def ends(rig):
        res = rig.simulate(1.0, n_out=3, backend="casadi")
        return res["integral.y"][-1], res["pulses.y"][-1]
    for k, rig in made.items():
        assert ends(rig) == pytest.approx(want[k], rel=1e-6), k
    monkeypatch.setattr(flatten_module, "flatten", lambda root: pytest.fail("compiled again"))
    for k in made:                                     # read back: each its own
        assert ends(table_rig([1.0, k[0]], k[1])) == pytest.approx(want[k], rel=1e-6), k
