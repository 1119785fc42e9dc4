"""An oil circuit fed by pressure sources alone (volumes, orifices, valves,
signals) cannot hold a pressure above the highest of its sources' and start
pressures: a run that shows one is not accurate enough, and its summary says
so (ImplausibleResultWarning naming the volume and the tolerances). A rig
with anything else that can raise a pressure (a hammer, a flow source, a
component of unknown kind) has no such bound, and no check."""
import warnings

import pytest

import pdbfs
from pdbfs.components import blocks as B
from pdbfs.components import hydraulic as H
from pdbfs.errors import ImplausibleResultWarning
from pdbfs.models import paper_rig

SUPPLY = 1e7


class Filling(pdbfs.Rig):
    """A 1 l volume filled through an orifice from a pressure given as a signal."""

    def declare(self):
        self.cmd = B.Constant(k=SUPPLY, unit="Pa")
        self.src = H.SignalPressure()
        self.orifice = H.Orifice()
        self.vol = H.Volume()
        self.connect(self.cmd.y, self.src.u)
        self.connect(self.src.port, self.orifice.port_a)
        self.connect(self.orifice.port_b, self.vol.port)


class Pumped(pdbfs.Rig):
    """A volume filled by a flow source: its pressure has no bound of a source."""

    def declare(self):
        self.pump = H.FlowSource(Q=1e-5)
        self.vol = H.Volume()
        self.connect(self.pump.port, self.vol.port)


def _warnings(rig, **kw):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rig.simulate(0.05, **kw).summary()
    return [str(w.message) for w in caught if issubclass(w.category, ImplausibleResultWarning)]


def test_the_bound_is_the_circuits_sources_and_stores():
    assert Filling().compile().pressure_bound == {"sources": ["src.port.p"], "stores": ["vol.p"]}
    assert paper_rig().compile().pressure_bound is None       # the hammer raises the pressure
    assert Pumped().compile().pressure_bound is None


def test_a_pressure_above_every_source_warns_naming_the_volume_and_the_tolerance():
    # (the compiled explicit method at these tolerances: 24 % above its supply;
    # the check reads the result, the same on either back end)
    found = _warnings(Filling(), backend="c", rtol=1e-2, atol=1e-2)
    assert len(found) == 1, found
    assert "vol.p reaches" in found[0] and "above every source's" in found[0]
    assert "rtol = 0.01" in found[0] and f"at most {SUPPLY:.10g} Pa" in found[0]


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_an_accurate_run_stays_below_its_sources_and_says_nothing(backend):
    assert _warnings(Filling(), backend=backend) == []
