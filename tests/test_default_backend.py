"""The default backend ("auto"): the compiled backend wherever it can be
built, CasADi with one BackendFallbackWarning where it cannot; the compiled
library found again by the DAE's fingerprint without code generation."""
import warnings

import numpy as np
import pytest

from pdbfs.errors import BackendFallbackWarning
from pdbfs.models import paper_rig
from pdbfs.simulation.run import compiled_build as build
from pdbfs.simulation import Simulator


def test_the_default_is_the_compiled_backend_and_agrees_with_casadi():
    rig = paper_rig()
    with warnings.catch_warnings():
        warnings.simplefilter("error", BackendFallbackWarning)
        d = rig.simulate()
    assert d.settings["backend"] == "c" and d.stats["backend"] == "c"
    a = rig.simulate(backend="casadi")
    assert a.settings["backend"] == "casadi"
    pa, pd = a["oil.pressure"], d["oil.pressure"]
    assert np.max(np.abs(pa - pd)) < 1e-6 * pa.max()
    assert d.summary()["peak_pressure"] == pytest.approx(a.summary()["peak_pressure"], rel=1e-7)


def test_without_a_compiler_the_default_falls_back_to_casadi_with_one_note(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))          # nothing cached
    monkeypatch.setenv("CC", str(tmp_path / "no-such-cc"))
    monkeypatch.setenv("PDBFS_SUNDIALS_BUILD", "0")
    rig = paper_rig()
    with pytest.warns(BackendFallbackWarning, match="rig .*simulating with CasADi") as rec:
        r = rig.simulate(n_out=11)
        r2 = rig.simulate(n_out=11)                               # decided once: no second note
    assert len([w for w in rec if w.category is BackendFallbackWarning]) == 1
    assert len(str(rec[0].message).splitlines()) == 1
    assert r.settings["backend"] == "casadi" and r2.settings["backend"] == "casadi"
    assert r["oil.pressure"].max() > 0


def test_the_library_is_reused_by_fingerprint_without_code_generation(monkeypatch):
    rig = paper_rig()
    Simulator.of(rig.compile()).compiled()                        # built or found once
    before = build.BUILDS

    def no_codegen(*a, **k):
        raise AssertionError("C generated again for an unchanged rig")
    monkeypatch.setattr(build, "generate", no_codegen)
    fresh = paper_rig().compile()                                 # another DAE object, same rig
    assert fresh is not rig.compile()
    r = Simulator.of(fresh).run(backend="c")
    assert build.BUILDS == before and r["oil.pressure"].max() > 0


def test_the_fingerprint_changes_with_the_equations():
    a = build.fingerprint(paper_rig().compile())
    assert a == build.fingerprint(paper_rig().compile())
    assert a != build.fingerprint(paper_rig(law="lankarani-nikravesh").compile())
