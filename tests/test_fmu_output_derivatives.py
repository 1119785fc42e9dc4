"""Output derivatives in Co-Simulation (FMI 2.0 fmi2GetRealOutputDerivatives,
FMI 3.0 fmi3GetOutputDerivatives; maxOutputDerivativeOrder 2): the first
and second time derivatives of the outputs at the communication point, from
the model's own derivatives (d/dt + d/dx der(x), the inputs' slopes in
d/dt), against central differences of the FMU's own trajectory at rtol
1e-12; the closed loop's controller, whose output follows its input
directly, with that input on a line. A master that extrapolates with them
(pdbfs's, interpolate=True) converges at second order, with half the error
of the outputs' differences over the step before."""
import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

import fmu_support as T
import ssp_support as S
from pdbfs.fmu import cosimulate

H = 1e-6                 # s: the communication step of the finite differences
N = 1000                 # the point where the derivatives are asked (1 ms)


class Slave:
    """A co-simulation instance (FMI 2.0 or 3.0) of the plant or the controller at rtol 1e-12."""

    def __init__(self, kind, version, name):
        path = S.fmu_of(kind, version)
        md = fmpy.read_model_description(path)
        self.v3 = version == 3
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        cls = FMU3Slave if self.v3 else FMU2Slave
        self.s = cls(guid=md.guid, unzipDirectory=fmpy.extract(path),
                     modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.log = []
        if self.v3:
            self.s.instantiate(logMessage=lambda env, st, cat, msg: self.log.append(msg.decode()))
        else:
            self.rec = T.Recorder(name)
            self.rec.clear()
            self.s.instantiate(callbacks=self.rec.callbacks)
        if self.v3:
            self.s.enterInitializationMode(tolerance=1e-12, startTime=0.0)
        else:
            self.s.setupExperiment(tolerance=1e-12, startTime=0.0)
            self.s.enterInitializationMode()
        self.md = md

    def errors(self):
        return self.log if self.v3 else self.rec.errors()

    def set(self, name, value):
        (self.s.setFloat64 if self.v3 else self.s.setReal)([self.vr[name]], [value])

    def get(self, name):
        return (self.s.getFloat64 if self.v3 else self.s.getReal)([self.vr[name]])[0]

    def rates(self, name, orders):
        get = self.s.getOutputDerivatives if self.v3 else self.s.getRealOutputDerivatives
        return get([self.vr[name]] * len(orders), list(orders))


def _trajectory(s, output, n, drive=None):
    """The output's (first, second) derivatives the FMU gives at step n, and
    their central differences over its trajectory around it; ``drive(t)``
    sets the inputs at each communication point."""
    out, ders = [], None
    for k in range(n + 2):
        if drive:
            drive(k * H)
        if k == n:
            ders = s.rates(output, (1, 2))
        out.append(s.get(output))
        s.s.doStep(k * H, H)
    y = np.array(out)
    return ders, (y[n + 1] - y[n - 1]) / (2 * H), (y[n + 1] - 2 * y[n] + y[n - 1]) / H ** 2


@pytest.mark.parametrize("version", [2, 3])
def test_the_plants_pressure_derivatives_are_its_trajectorys(version):
    """The valve part open (0.3): the chamber fills, p' ~ 1e10 Pa/s."""
    s = Slave("plant", version, f"plant{version}")
    assert s.md.coSimulation.maxOutputDerivativeOrder == 2
    s.set("opening", 0.3)
    s.s.exitInitializationMode()
    (d1, d2), fd1, fd2 = _trajectory(s, "sensor.y", 1000)
    assert d1 > 1e9 and d2 < 0
    assert d1 == pytest.approx(fd1, rel=1e-6) and d2 == pytest.approx(fd2, rel=1e-5)
    # a state that is an output: its first derivative is der(x)
    assert s.rates("chamber.p_law", (1,))[0] == pytest.approx(s.get("der(chamber.p_law)"), rel=1e-14)
    s.s.terminate()
    s.s.freeInstance()


def test_the_controllers_command_follows_its_inputs_line():
    """pid.y follows the control error at once (its proportional part): on
    the target's rise, with the measurement 1 MPa below the target on a
    line of the target's slope (FMI 2.0 input derivatives), the command's
    derivative is the integral part's alone, k e / Ti = 160 1/s (held, the
    proportional part would add k times the target's slope, 2400 1/s)."""
    from pdbfs.models import TARGET
    s = Slave("controller", 2, "controller")
    s.s.exitInitializationMode()
    rate = (TARGET[1][2] - TARGET[1][1]) / (TARGET[0][2] - TARGET[0][1])     # Pa/s

    def drive(t):
        if t >= TARGET[0][1]:
            s.set("measured", float(np.interp(t, *TARGET)) - 1e6)
            s.s.setRealInputDerivatives([s.vr["measured"]], [1], [rate])
    (d1, d2), fd1, fd2 = _trajectory(s, "pid.y", 2000, drive)
    y = s.get("pid.y")
    s.s.terminate()
    s.s.freeInstance()
    assert 0 < y < 1
    assert d1 == pytest.approx(8e-8 * 1e6 / 5e-4, rel=1e-9) and d1 == pytest.approx(fd1, rel=1e-6)
    assert abs(d2) < 1e-6 * abs(d1) / H and abs(fd2) < 1e-6 * abs(d1) / H      # a line: no curvature


@pytest.mark.parametrize("version", [2, 3])
def test_what_is_not_an_output_or_order_is_refused_in_one_line(version):
    s = Slave("plant", version, f"refuse{version}")
    s.s.exitInitializationMode()
    s.s.doStep(0.0, 1e-4)
    for name, order, words in (("sensor.y", 3, "order 3: the first and second derivatives are given"),
                               ("der(chamber.p_law)", 1, "is not an output or a state"),
                               ("chamber.V", 1, "is not an output or a state")):
        with pytest.raises(FMICallException):
            s.rates(name, (order,))
        assert words in s.errors()[-1], s.errors()
    s.s.freeInstance()


def _errors(steps):
    """pdbfs's master with interpolated inputs: the largest error of the plant's pressure at each step."""
    errors = []
    for h in steps:
        r = cosimulate(S.loop_ssp(2), h, outputs=["plant.sensor.y"], interpolate=True, tolerance=1e-10)
        errors.append(S.max_error(r.t, r["plant.sensor.y"]))
    return errors


def test_a_master_extrapolating_with_them_gets_second_order(monkeypatch):
    """The inputs' slopes from the FMUs' output derivatives, against the
    outputs' differences over the step before (measured: 73, 19, 5.1 kPa at
    50, 25, 12.5 us, against 150, 40, 10 kPa)."""
    import pdbfs.fmu.master as master
    steps = [5e-5, 2.5e-5, 1.25e-5]
    own = _errors(steps)
    monkeypatch.setattr(master._Member, "derivatives", property(lambda self: False, lambda self, v: None),
                        raising=False)
    differences = _errors(steps)
    assert S.order(steps, own) == pytest.approx(2.0, abs=0.1), own
    assert all(a < 0.6 * b for a, b in zip(own, differences)), (own, differences)
