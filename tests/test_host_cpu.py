"""The compiled backend's library is built for this machine's vector unit
(pdbfs.native.toolchain.host_cpu_flags: x86-64-v3 where the CPU has AVX2):
every number it gives is the one of a build for the baseline CPU, bit for
bit (no fused multiply-add, no reordered sums), and the flag is in the
library's cache key, so a cache shared with another CPU never hands it this
library."""
from pathlib import Path

import numpy as np
import pytest

from pdbfs.models import paper_rig
from pdbfs.native import toolchain
from pdbfs.simulation.run import compiled as C
from pdbfs.simulation.run import compiled_build
from pdbfs.simulation.run.simulator import Simulator

FLAGS = toolchain.host_cpu_flags(toolchain.compiler(toolchain.host_target()))
if not FLAGS:
    pytest.skip("this machine's compiler or CPU gets no vector-unit flag (not x86-64-v3, or $CC)",
                allow_module_level=True)


class _At(C.CompiledODE):
    """The library at a given path."""

    def __init__(self, dae, path):
        self._path = Path(path)
        super().__init__(dae)

    def _build(self, dae):
        return self._path


@pytest.fixture(scope="module")
def both(tmp_path_factory):
    """(library for this CPU, library for the baseline CPU) of the paper rig, and the rig."""
    rig = paper_rig()
    dae = rig.compile()
    here = compiled_build.build(dae)
    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(toolchain, "host_cpu_flags", lambda cmd: [])
        baseline = compiled_build.build(dae)
    finally:
        mp.undo()
    return _At(dae, here), _At(dae, baseline), rig


def test_the_flag_is_part_of_the_key(both):
    here, baseline, _ = both
    assert here.path != baseline.path


@pytest.mark.parametrize("method", ["erk", "adams", "bdf"])
def test_every_number_is_the_baseline_builds_bit_for_bit(both, method):
    here, baseline, rig = both
    sim = Simulator.of(rig)
    grid = np.linspace(0.0, 0.02, 2001)
    for v0, k in [(2.73, 2.228e8), (5.5, 4e8), (1.5, 1e8)]:
        p = sim.param_vector({"hammer.v0": v0, "oil.k": k})
        x0 = sim.start_vector(p, None)
        rtol = 5e-8 if method == "erk" else 1e-8
        a = here.run_summary(grid, x0, p, rtol, 1e-10, method, checked=True)
        b = baseline.run_summary(grid, x0, p, rtol, 1e-10, method, checked=True)
        assert a[1].ok and b[1].ok
        assert np.array_equal(a[0], b[0])                          # the trajectory
        assert np.array_equal(a[2], b[2], equal_nan=True)          # the summary
        assert a[1].steps == b[1].steps and a[1].rhs_evals == b[1].rhs_evals
    P = np.array([sim.param_vector({"hammer.v0": v}) for v in (1.7, 3.1, 4.9)])
    sa, sb = here.summaries(P, 0.02, 5e-8, 1e-10, method), baseline.summaries(P, 0.02, 5e-8, 1e-10, method)
    assert np.array_equal(sa[0], sb[0], equal_nan=True)           # the sweep driver's
