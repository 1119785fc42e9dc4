"""FMI 3.0 Co-Simulation's intermediate update and early return
(providesIntermediateUpdate, canReturnEarlyAfterIntermediateUpdate): inside
fmi3DoStep the importer's callback is called after each internal solver
step, its outputs readable there (intermediateUpdate="true") and equal to
what a communication point at that time reads; asked to return early, the
FMU stops at the time asked and goes on from there on the same trajectory.
Only the outputs are read there; nothing is set."""
import xml.etree.ElementTree as ET
import zipfile

import fmpy
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

import ssp_support as S

OPENING = 0.3


class Plant:
    """The closed loop's plant (FMI 3.0) with its valve held at OPENING."""

    def __init__(self, name, update=None, early=False, required=()):
        path = S.fmu_of("plant", 3)
        md = fmpy.read_model_description(path)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.log, self.seen, self.ask = [], [], None
        self.s = FMU3Slave(guid=md.guid, unzipDirectory=fmpy.extract(path),
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        self.s.instantiate(earlyReturnAllowed=early, intermediateUpdate=update and self._update,
                           requiredIntermediateVariables=[self.vr[n] for n in required],
                           logMessage=lambda env, st, cat, msg: self.log.append(msg.decode()))
        self.s.enterInitializationMode(tolerance=1e-10, startTime=0.0)
        self.s.setFloat64([self.vr["opening"]], [OPENING])
        self.s.exitInitializationMode()
        self.update = update

    def _update(self, env, t, set_requested, get_allowed, finished, can_return_early, asked, when):
        self.seen.append((t, bool(set_requested), bool(get_allowed), bool(finished), bool(can_return_early)))
        self.update(self, t, asked, when)

    def get(self, *names):
        return self.s.getFloat64([self.vr[n] for n in names])


def test_the_model_description_offers_it():
    with zipfile.ZipFile(S.fmu_of("plant", 3)) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    cs = root.find("CoSimulation")
    assert cs.get("providesIntermediateUpdate") == "true" == cs.get("canReturnEarlyAfterIntermediateUpdate")
    marked = {v.get("name") for v in root.find("ModelVariables") if v.get("intermediateUpdate") == "true"}
    outputs = {v.get("name") for v in root.find("ModelVariables") if v.get("causality") == "output"}
    assert marked == outputs and "sensor.y" in marked


def test_the_outputs_read_inside_a_step_are_the_trajectorys():
    """One 2 ms step: the callback at each internal step (increasing times
    inside the step, outputs readable, nothing to set); the pressure read
    there equals a second instance's at communication points at those times."""
    values = []

    def update(plant, t, asked, when):
        values.append(plant.get("sensor.y", "chamber.p_law"))
    a = Plant("seen", update)
    a.s.doStep(0.0, 2e-3)
    times = np.array([t for t, *_ in a.seen])
    assert len(times) > 20 and np.all(np.diff(times) > 0) and 0 < times[0] and times[-1] < 2e-3
    assert all(not s and g and f and not c for _, s, g, f, c in a.seen)        # no early return allowed
    assert not any("intermediate" in m and "not" in m for m in a.log), a.log
    b = Plant("points")
    t0 = 0.0
    for t, (p, p_law) in zip(times[::7], values[::7]):
        b.s.doStep(t0, t - t0)
        t0 = t
        assert b.get("sensor.y")[0] == pytest.approx(p, rel=1e-12) and p == p_law
    for plant in (a, b):
        plant.s.freeInstance()


def test_only_outputs_are_read_and_nothing_is_set_inside_a_step():
    errors = []

    def update(plant, t, asked, when):
        if not errors:
            for call in (lambda: plant.get("der(chamber.p_law)"), lambda: plant.get("valve.A"),
                         lambda: plant.s.setFloat64([plant.vr["opening"]], [0.5]),
                         lambda: plant.s.doStep(t, 1e-4)):
                try:
                    call()
                    errors.append("accepted")
                except FMICallException:
                    errors.append(plant.log[-1])
    a = Plant("refusals", update)
    a.s.doStep(0.0, 1e-4)
    assert errors[0].endswith("is not an output: in an intermediate update only the outputs "
                              '(intermediateUpdate="true") are read') and "valve.A" not in errors[1]
    assert "is not an output" in errors[1]
    assert errors[2:] == ["fmi3SetFloat64: must not be called in state 'intermediate update'",
                          "fmi3DoStep: must not be called in state 'intermediate update'"], errors
    assert a.get("opening")[0] == OPENING
    a.s.freeInstance()


@pytest.mark.parametrize("where", ["past the step", "inside the step"])
def test_an_early_return_stops_where_asked_and_goes_on_alike(where):
    """Asked at the first internal step past 0.7 ms to return at 0.75 ms (a
    time past that step: the FMU integrates on to it), or half-way through
    that step (its dense output): fmi3DoStep returns early there, and the run
    from there is the one without early return, to the bit."""
    def update(plant, t, asked, when):
        if t > 7e-4 and plant.ask is None:
            plant.ask = 7.5e-4 if where == "past the step" else 0.5 * (plant.seen[-2][0] + t)
            asked[0], when[0] = True, plant.ask
    a = Plant("early", update, early=True)
    event, terminate, early, last = a.s.doStep(0.0, 2e-3)
    assert early and last == a.ask and all(c for *_, c in a.seen)
    assert (a.seen[-1][0] < last) == (where == "past the step")
    a.s.doStep(last, 2e-3 - last)
    b = Plant("whole")
    b.s.doStep(0.0, last)
    b.s.doStep(last, 2e-3 - last)
    assert a.get("sensor.y")[0] == b.get("sensor.y")[0]        # the same steps: the same numbers
    for plant in (a, b):
        plant.s.freeInstance()


def test_required_intermediate_variables_must_be_outputs():
    with pytest.raises(Exception):
        Plant("required", lambda *a: None, required=("opening",))
    ok = Plant("required-ok", lambda *a: None, required=("sensor.y",))
    ok.s.freeInstance()
