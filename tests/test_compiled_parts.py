"""The compiled backend's library in parts (simulation/run/compiled_build.py):
the drivers compiled once per machine, the explicit method's arithmetic once
per state count, and per rig only its own C, linked with them. The numbers
are those of a library compiled whole with the rig's sizes as constants (as
every library was before the drivers were shared), bit for bit; the
per-machine parts are compiled once, again when a source changes, and two
processes building them at once leave one whole set."""
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pdbfs.files import cache_folder
from pdbfs.models import RIGS, hydraulic_pulse_rig, paper_rig, split_piston_rig
from pdbfs.native import toolchain
from pdbfs.native.codegen import ERK_SIZE_HEADER, LIBRARY_C, erk_size_header
from pdbfs.simulation import Simulator
from pdbfs.simulation.run import compiled as C
from pdbfs.simulation.run import compiled_build as cb


class _At(C.CompiledODE):
    """The library at a given path."""

    def __init__(self, dae, path, cvode=None):
        self._path = Path(path)
        super().__init__(dae, cvode=cvode)

    def _build(self, dae):
        return self._path


def _whole(dae, sd, folder: Path) -> Path:
    """The library of ``dae`` compiled in one command, every driver with the
    rig's sizes as constants: pdbfs_batch_model.h's run-time fields replaced
    by the values the rig's pdbfs_batch_model.c gives them."""
    cb.write_rig_sources(dae, folder)
    fields = dict(re.findall(r"\.(\w+) = ([^,\n]+),", (folder / cb.RIG_SIZES).read_text()))
    for f in cb._sources(sd):
        shutil.copyfile(f, folder / f.name)
    header = (LIBRARY_C / "pdbfs_batch_model.h").read_text()
    (folder / "pdbfs_batch_model.h").write_text(
        re.sub(r"\(pdbfs_rig\.(\w+)\)", lambda m: f"({fields[m.group(1)]})", header))
    (folder / ERK_SIZE_HEADER).write_text(erk_size_header(dae.x.numel()))
    sources = [folder / f.name for f in cb._sources(sd) if f.suffix == ".c"] + \
        [folder / "pdbfs_model_funcs.c"]
    out = folder / "whole.so"
    subprocess.run(cb._command(sources, out, [folder], sd, toolchain.host_target()), check=True,
                   capture_output=True, env=toolchain.zig_env())
    return out


def _same(a, b) -> bool:
    return np.array_equal(np.asarray(a, float), np.asarray(b, float), equal_nan=True)


@pytest.mark.parametrize("make", [paper_rig, RIGS["paper-hydraulic-oil"], hydraulic_pulse_rig],
                         ids=["contact force", "a declared range", "time events, no contact"])
def test_the_parts_give_the_numbers_of_the_library_compiled_whole(make, tmp_path):
    rig = make()
    dae = rig.compile()
    sd = cb.sundials_for(None)
    parts, whole = _At(dae, cb.build(dae, sd)), _At(dae, _whole(dae, sd, tmp_path))
    assert sorted(parts.roles) == sorted(whole.roles)
    sim = Simulator.of(rig)
    p = sim.param_vector()
    x0 = sim.start_vector(p)
    t = np.linspace(0.0, 0.02, 401)
    methods = ["erk", "adams", "bdf"] if parts.cvode else ["erk"]
    for method in methods:
        for start in (x0, np.concatenate([x0, np.zeros(parts.nq)])):
            (Xa, sa), (Xb, sb) = parts.run(t, start, p, 1e-8, 1e-10, method), \
                whole.run(t, start, p, 1e-8, 1e-10, method)
            assert sa.code == sb.code == 0 and sa.stats["steps"] == sb.stats["steps"] > 0
            assert _same(Xa, Xb), method
        a, b = parts.run_summary(t, x0, p, 1e-8, 1e-10, method), \
            whole.run_summary(t, x0, p, 1e-8, 1e-10, method)
        assert _same(a[0], b[0]) and _same(a[2], b[2]) and a[3:5] == b[3:5], method
        P = np.array([p * f for f in (0.9, 1.0, 1.1)])
        a, b = parts.summaries(P, 0.02, 1e-8, 1e-10, method), whole.summaries(P, 0.02, 1e-8, 1e-10, method)
        assert _same(a[0], b[0]) and list(a[1]) == list(b[1]) and a[2] == b[2], method


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    """Empty folders for the rigs' libraries and the drivers; each compiler run counted."""
    monkeypatch.setattr(cb, "cache_dir", lambda: tmp_path / "compiled")
    monkeypatch.setattr(cb, "drivers_dir", lambda: tmp_path / "drivers")
    runs = []
    real = cb.run_compiler
    monkeypatch.setattr(cb, "run_compiler", lambda cmd, what: (runs.append(what), real(cmd, what)))
    return tmp_path, runs


def _objects(folder: Path) -> dict:
    return {o.name: o.stat().st_mtime_ns for o in folder.rglob("*.o")}


def test_a_new_rig_compiles_only_its_own_c(fresh):
    tmp, runs = fresh
    sd = cb.sundials_for(None)
    before = cb.DRIVER_BUILDS
    first = paper_rig().compile()
    cb.build(first, sd)
    drivers = [f for f in cb._sources(sd) if f.suffix == ".c" and f.name != cb.SIZED_C]
    assert cb.DRIVER_BUILDS == before + 1 and len(runs) == len(drivers) + 2   # + 6 states, the rig
    kept = _objects(tmp / "drivers")
    # another structure of the same state count: its library alone
    del runs[:]
    cb.build(RIGS["paper-hc"]().compile(), sd)
    assert runs == ["the compiled model of rig pdbfs_hc"]
    # a new state count: its explicit method, once, and the library
    del runs[:]
    split = split_piston_rig(2).compile()
    cb.build(split, sd)
    assert runs == [f"the explicit method for {split.x.numel()} states",
                    f"the compiled model of rig {split.name}"]
    assert cb.DRIVER_BUILDS == before + 1
    now = _objects(tmp / "drivers")
    assert {k: now[k] for k in kept} == kept and len(now) == len(kept) + 1
    assert len(list((tmp / "drivers").iterdir())) in (1, 2)     # one folder (and its lock)


def test_a_changed_or_damaged_driver_is_compiled_again(fresh, monkeypatch):
    tmp, runs = fresh
    sd = cb.sundials_for(None)
    objects = cb.drivers(sd)
    before = cb.DRIVER_BUILDS
    # a damaged folder (an object gone): built again, whole
    objects[0].unlink()
    again = cb.drivers(sd)
    assert again == objects and all(o.is_file() for o in again) and cb.DRIVER_BUILDS == before + 1
    # a changed source: another folder
    pulse = next(f for f in cb.DRIVERS if f.name == "pdbfs_pulse.c")
    changed = tmp / "pdbfs_pulse.c"
    changed.write_text(pulse.read_text() + "\n/* changed */\n")
    monkeypatch.setattr(cb, "DRIVERS", tuple(changed if f == pulse else f for f in cb.DRIVERS))
    other = cb.drivers(sd)
    assert other[0].parent != objects[0].parent and cb.DRIVER_BUILDS == before + 2
    rig = paper_rig()
    lib = _At(rig.compile(), cb.build(rig.compile(), sd))
    sim = Simulator.of(rig)
    p = sim.param_vector()
    X, st = lib.run(np.linspace(0, 0.02, 201), sim.start_vector(p), p, 1e-8, 1e-10, "erk")
    assert st.ok and np.isfinite(X).all()


BUILD = """
import json, sys
from pdbfs.models import PaperRig
from pdbfs.simulation.run import compiled_build
class Rig(PaperRig):
    name = sys.argv[1]
r = Rig().simulate(backend="c", method="erk")
print(json.dumps([compiled_build.DRIVER_BUILDS, float(r["oil.pressure"].max())]))
"""


def test_two_processes_building_the_drivers_at_once_leave_one_whole_set(tmp_path):
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"),
               ZIG_GLOBAL_CACHE_DIR=os.environ.get("ZIG_GLOBAL_CACHE_DIR", str(cache_folder() / "zig")))
    procs = [subprocess.Popen([sys.executable, "-c", BUILD, f"pdbfs_concurrent_{k}"], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for k in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], [e[-800:] for _, e in outs]
    (built_a, peak_a), (built_b, peak_b) = (json.loads(o.strip().splitlines()[-1]) for o, _ in outs)
    assert built_a + built_b == 1 and peak_a == peak_b
    assert peak_a == paper_rig().simulate(backend="c", method="erk")["oil.pressure"].max()
    folders = [d for d in (tmp_path / "cache" / "pdbfs" / "drivers").iterdir() if d.is_dir()]
    assert len(folders) == 1                                 # no half-built folder left
    sd = None                                                # no CVODE in a new cache folder
    expected = {f"{f.stem}.o" for f in cb._sources(sd) if f.suffix == ".c" and f.name != cb.SIZED_C}
    assert {o.name for o in folders[0].iterdir()} == expected | {f"{Path(cb.SIZED_C).stem}-6.o"}
