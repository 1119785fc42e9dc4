"""The compiled DAE kept on disk (pdbfs/modelling/dae_cache.py): a rig
compiled before is read back, never one whose declaration or code has
changed since; a one-shot `pdbfs simulate` of a known rig imports neither
the structural analysis nor scipy."""
import importlib
import json
import math
import subprocess
import sys

import pytest

from pdbfs.modelling import dae_cache
from pdbfs.modelling import flatten as flatten_module
from pdbfs.models import RIGS, paper_rig

OSCILLATOR = '''
from pdbfs import Parameter, Rig, State, der, eq


class Oscillator(Rig):
    """A mass on a spring, started at x = 0 with v = v0."""
    k = Parameter(100.0, "N/m", "stiffness", positive=True)
    m = Parameter(1.0, "kg", "mass", positive=True)

    def declare(self):
        self.x = State("m", "position", start=0.0)
        self.v = State("m/s", "velocity", start=1.0)

    def equations(self):
        return [eq(der(self.x), self.v), eq(der(self.v), -{factor} * self.k / self.m * self.x)]
'''


@pytest.fixture
def oscillator_module(tmp_path, monkeypatch):
    """A rig module in tmp_path that the cache treats as one of pdbfs's own
    (its folder hashed as a package's), to be rewritten by the test."""
    monkeypatch.setattr(sys, "dont_write_bytecode", True)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    name = f"pdbfs_cache_test_{tmp_path.name.replace('-', '_')}"
    original = dae_cache._package_dir
    monkeypatch.setattr(dae_cache, "_package_dir",
                        lambda mod: tmp_path / f"{name}.py" if mod == name else original(mod))
    path = tmp_path / f"{name}.py"

    def write(factor):
        path.write_text(OSCILLATOR.format(factor=factor))
        if name in sys.modules:
            return importlib.reload(sys.modules[name])
        return importlib.import_module(name)
    yield write
    sys.modules.pop(name, None)


def _amplitude(rig):
    res = rig.simulate(0.7, n_out=7001, backend="casadi")   # longer than a period of both
    return max(res["x"])


def test_an_edited_component_is_compiled_again_never_read_stale(oscillator_module, monkeypatch):
    mod = oscillator_module(1)
    assert dae_cache.declaration_key(mod.Oscillator()) is not None
    # v0 / omega, omega = sqrt(factor k / m)
    assert _amplitude(mod.Oscillator()) == pytest.approx(1 / math.sqrt(100.0), rel=1e-6)
    mod = oscillator_module(4)                      # the equation changed, nothing else
    assert _amplitude(mod.Oscillator()) == pytest.approx(1 / math.sqrt(400.0), rel=1e-6)
    # unchanged since: read back, nothing flattened
    monkeypatch.setattr(flatten_module, "flatten", lambda root: pytest.fail("compiled again"))
    assert _amplitude(mod.Oscillator()) == pytest.approx(1 / math.sqrt(400.0), rel=1e-6)


def test_a_changed_declaration_changes_the_key():
    keys = {name: dae_cache.declaration_key(make()) for name, make in RIGS.items()}
    assert None not in keys.values()
    assert len(set(keys.values())) == len(keys)            # every rig its own
    assert dae_cache.declaration_key(paper_rig()) == keys["paper"]   # and the same again
    rig = paper_rig()
    rig.hammer.bind("m", 3000.0)                            # a default changed: another DAE
    assert dae_cache.declaration_key(rig) != keys["paper"]


def test_a_rig_of_the_users_own_classes_is_not_kept():
    from pdbfs import Rig, State, der, eq

    class Mine(Rig):
        def declare(self):
            self.x = State("m", "position", start=1.0)

        def equations(self):
            return [eq(der(self.x), -self.x)]
    assert dae_cache.declaration_key(Mine()) is None
    assert Mine().simulate(0.1, n_out=3, backend="casadi")["x"][-1] == pytest.approx(
        math.exp(-0.1), rel=1e-6)


def test_a_damaged_entry_is_rebuilt(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    key = dae_cache.declaration_key(paper_rig())
    folder = dae_cache._cache_dir()
    folder.mkdir(parents=True)
    (folder / f"{key}.pkl").write_bytes(b"not a pickle")
    assert dae_cache.load(key) is None
    fresh = paper_rig().compile()                        # rebuilt, and kept again
    assert dae_cache.load(key).x_names == fresh.x_names


def test_the_dae_read_back_simulates_as_the_one_built(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    built = paper_rig().simulate(backend="casadi").summary()
    monkeypatch.setattr(flatten_module, "flatten", lambda root: pytest.fail("compiled again"))
    again = paper_rig().simulate(backend="casadi").summary()
    assert again == built


def test_a_one_shot_simulate_of_a_known_rig_imports_no_structural_analysis(tmp_path):
    run = [sys.executable, "-c", "import sys, pdbfs.cli; s = pdbfs.cli.main(['simulate', "
           f"'--json', '--out', {str(tmp_path)!r}]); print(sorted(m for m in sys.modules "
           "if m.startswith(('scipy', 'pdbfs.modelling.structure', 'pdbfs.modelling.passes.blt', "
           "'pdbfs.studies', 'pandas')))); sys.exit(s)"]
    subprocess.run(run, check=True, capture_output=True)        # the caches filled
    out = subprocess.run(run, check=True, capture_output=True, text=True).stdout.splitlines()
    assert json.loads(out[0])["complete"] is True
    assert out[1] == "[]"
