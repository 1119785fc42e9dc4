"""pdbfs as a newcomer meets it: `pdbfs --help` in plain text, help for every
option, commands that write files only where --out says, the example files
shipped in the package, and a feature whose extra is missing saying which
one to install (one line, exit 2, before any work)."""
import argparse
import subprocess
import sys
from pathlib import Path

import pytest

import pdbfs
from pdbfs.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[1]


def cli(*args, cwd, env=None, timeout=300):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd, env=env, timeout=timeout)


def files_in(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


# -- help -------------------------------------------------------------------------------
def subparsers(ap):
    for a in ap._actions:
        if isinstance(a, argparse._SubParsersAction):
            return a.choices
    return {}


def test_every_option_of_every_command_has_help():
    ap = build_parser()
    missing = []

    def walk(p, path):
        for a in p._actions:
            if isinstance(a, argparse._SubParsersAction):
                for name, sp in a.choices.items():
                    walk(sp, f"{path} {name}")
            elif not a.help or a.help == argparse.SUPPRESS:
                missing.append(f"{path} {'/'.join(a.option_strings) or a.dest}")
    walk(ap, "pdbfs")
    assert not missing, missing


def test_pdbfs_help_lists_every_command_in_plain_text(tmp_path):
    r = cli("--help", cwd=tmp_path)
    assert r.returncode == 0
    commands = subparsers(build_parser())
    assert len(commands) >= 13
    listed = [line.split()[0] for line in r.stdout.splitlines()
              if line.startswith("    ") and line.split()]
    assert [c for c in commands if c not in listed] == [], r.stdout
    assert "``" not in r.stdout and ":class:" not in r.stdout, r.stdout
    description = r.stdout.split("\n\n")[1]
    assert description.rstrip().endswith("."), description   # a whole sentence, not cut off


# -- files only where --out says --------------------------------------------------------
def test_simulate_json_in_an_empty_folder_leaves_it_empty(tmp_path):
    r = cli("simulate", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert '"peak_pressure"' in r.stdout
    assert files_in(tmp_path) == []


@pytest.mark.parametrize("args", [
    ["simulate", "--t-end", "0.012"],
    ["sweep", "--set", "hammer.v0=2,3", "--t-end", "0.012", "--quiet"],
    ["design-map", "--x", "hammer.h=0.3:0.5", "--y", "oil.k=2e8:3e8", "--n", "2", "--quiet"],
], ids=lambda a: a[0])
def test_a_command_without_out_writes_nothing(args, tmp_path):
    r = cli(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "wrote" not in r.stdout
    assert files_in(tmp_path) == []


def test_simulate_with_out_writes_there(tmp_path):
    r = cli("simulate", "--t-end", "0.012", "--out", "res", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert files_in(tmp_path) == ["res", "res/results.csv", "res/results.png"]


# -- example files ------------------------------------------------------------------------
def test_example_data_are_the_documented_files():
    for name in ("kistler_synthetic.csv", "gun_target.csv", "gun_firing.csv"):
        path = pdbfs.example_data(name)
        assert isinstance(path, Path) and path.is_file()
        # the copy the docs' figures were made from, byte for byte
        assert path.read_bytes() == (ROOT / "docs" / "data" / name).read_bytes()


def test_an_unknown_example_is_one_line_naming_the_ones_there_are():
    with pytest.raises(pdbfs.DataError) as err:
        pdbfs.example_data("kistler.csv")
    text = str(err.value)
    assert "\n" not in text and "kistler.csv" in text
    assert "kistler_synthetic.csv" in text and "gun_target.csv" in text


def test_example_data_command_copies_and_refuses_to_clobber(tmp_path):
    r = cli("example-data", cwd=tmp_path)                  # a list, nothing written
    assert r.returncode == 0 and "kistler_synthetic.csv" in r.stdout
    assert files_in(tmp_path) == []
    r = cli("example-data", "--out", "data", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert files_in(tmp_path) == ["data", "data/gun_firing.csv", "data/gun_target.csv",
                                  "data/kistler_synthetic.csv", "data/valve_opening.csv"]
    r = cli("example-data", "--out", "data", cwd=tmp_path)   # again: nothing to do
    assert r.returncode == 0 and "already there" in r.stdout
    mine = tmp_path / "data" / "gun_target.csv"
    mine.write_text("time,p\n0,1\n")
    (tmp_path / "data" / "kistler_synthetic.csv").unlink()
    r = cli("example-data", "--out", "data", cwd=tmp_path)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "gun_target.csv" in r.stderr and "--force" in r.stderr
    assert mine.read_text() == "time,p\n0,1\n"                  # nothing copied at all
    assert not (tmp_path / "data" / "kistler_synthetic.csv").exists()
    r = cli("example-data", "--out", "data", "--force", cwd=tmp_path)
    assert r.returncode == 0
    assert mine.read_bytes() == pdbfs.example_data("gun_target.csv").read_bytes()


def test_the_calibrate_example_runs_on_the_shipped_trace(tmp_path):
    r = cli("calibrate", "--trace", str(pdbfs.example_data("kistler_synthetic.csv")),
            "--free", "hammer.v0", "--starts", "1", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert files_in(tmp_path) == []


# -- extras --------------------------------------------------------------------------------
#: what a core install lacks, hidden from a process
BLOCK = """
import importlib.abc, sys
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in {names!r}:
            raise ModuleNotFoundError(f"No module named {{name!r}}")
        return None
sys.meta_path.insert(0, Block())
import importlib.util
real = importlib.util.find_spec
def find_spec(name, package=None):
    if name.split('.')[0] in {names!r}:
        return None
    return real(name, package)
importlib.util.find_spec = find_spec
from pdbfs.cli import main
sys.exit(main(sys.argv[1:]))
"""
EXTRA_PACKAGES = ("dash", "diskcache", "multiprocess", "orjson", "dask", "distributed",
                  "pyarrow", "SALib")


def without_extras(args, cwd):
    code = BLOCK.format(names=set(EXTRA_PACKAGES))
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


@pytest.mark.parametrize("args,extra", [
    (["app"], "app"),
    (["sensitivity", "--range", "hammer.v0=2:4", "--n", "4"], "sensitivity"),
    (["sweep", "--set", "hammer.v0=2,3", "--format", "parquet", "--out", "s"], "parquet"),
    (["sweep", "--set", "hammer.v0=2,3", "--dask", "local"], "dask"),
], ids=lambda a: a if isinstance(a, str) else a[0])
def test_a_missing_extra_is_named_before_any_work(args, extra, tmp_path):
    r = without_extras(args, tmp_path)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and f"pip install 'pdbfs[{extra}]'" in lines[0], r.stderr
    assert files_in(tmp_path) == []


def test_a_core_sweep_streams_csv_without_pyarrow(tmp_path):
    r = without_extras(["sweep", "--sample", "lhs:4", "--range", "hammer.v0=2:4", "--t-end",
                        "0.012", "--out", "s", "--quiet"], tmp_path)
    assert r.returncode == 0, r.stderr
    chunks = list((tmp_path / "s" / "chunks").glob("chunk-*"))
    assert chunks and all(c.suffix == ".csv" for c in chunks)


def test_the_core_dependencies_hold_no_extra():
    tomllib = pytest.importorskip("tomllib")           # Python 3.11+
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = " ".join(meta["dependencies"]).lower()
    for name in ("dash", "dask", "pyarrow", "salib", "diskcache", "multiprocess", "orjson", "nptdms",
                 "asammdf"):
        assert name not in core, name
    extras = meta["optional-dependencies"]
    assert set(extras["all"][0].split("[")[1].rstrip("]").split(",")) == \
        {"app", "dask", "parquet", "sensitivity", "control", "lab"}
    assert meta["license"] == "BSD-3-Clause" and meta["license-files"] == ["LICENSE"]
    assert "BSD 3-Clause" in (ROOT / "LICENSE").read_text()


# -- reprs --------------------------------------------------------------------------------
def test_a_rig_shows_its_name_size_and_components():
    from pdbfs.models import RIGS
    rig = RIGS["paper"]()
    dae = rig.compile()
    text = repr(rig)
    assert text.startswith("<PaperRig 'pdbfs_paper'") and "object at 0x" not in text
    assert f"{dae.x.numel()} states" in text and f"{len(dae.params)} parameters" in text
    assert "hammer (Mass)" in text and "oil (OilColumn)" in text
    assert "<table>" in rig._repr_html_()


def test_a_result_shows_its_run_and_the_summary_it_has():
    from pdbfs.models import RIGS
    from pdbfs.simulation.results.reprs import number
    rig = RIGS["paper"]()
    res = rig.simulate(0.02, backend="c", method="erk")
    text = repr(res)
    s = res.summary()
    assert "rig pdbfs_paper" in text and "0 .. 0.02 s, 2001 points" in text
    assert "pulse complete" in text and number(s["peak_pressure"], "Pa") in text
    slow = rig.simulate(0.02, backend="casadi")
    text = repr(slow)                       # a repr integrates nothing
    assert "not computed yet" in text and "_summary" not in slow.__dict__
    cut = rig.simulate(0.003, backend="casadi", n_out=301)
    with pytest.warns(pdbfs.PulseIncompleteWarning):
        cut.summary()
    assert "pulse incomplete" in repr(cut)
    assert "<table>" in res._repr_html_()


def test_studies_show_what_they_found_in_a_line(tmp_path):
    from pdbfs.models import RIGS
    rig = RIGS["paper"]()
    sw = pdbfs.sweep(rig, {"hammer.v0": [2.0, 3.0]}, progress=False, t_end=0.012)
    assert repr(sw).startswith("<SweepResult of rig pdbfs_paper: points 2, 0 failed")
    d = pdbfs.design(rig, {"peak_pressure": 150e6}, free=["hammer.v0"])
    text = repr(d)
    assert text.startswith("<Design of rig pdbfs_paper") and "targets reached" in text
    assert f"hammer.v0 {d.params['hammer.v0']:.6g} m/s" in text
    for shown in (repr(sw), text):
        assert "array(" not in shown and "\n" not in shown and len(shown) < 500


def test_a_calibration_shows_its_fit_in_a_line():
    from pdbfs.models import RIGS
    c = pdbfs.calibrate(RIGS["paper"](), pdbfs.example_data("kistler_synthetic.csv"),
                        ["hammer.v0"], starts=1)
    text = repr(c)
    assert text.startswith("<Calibration of rig pdbfs_paper: fitted hammer.v0 ")
    assert f"{c.params['hammer.v0']:.6g} m/s +- {c.std['hammer.v0']:.6g} m/s" in text
    assert "array(" not in text and "\n" not in text and len(text) < 500


def test_an_export_for_several_platforms_says_each_as_it_ends(tmp_path, capfd):
    """The first export for every platform runs for minutes: each platform's
    binary is said on stderr with its share of the whole as it is built."""
    from pdbfs.models import RIGS
    RIGS["paper"]().export_fmu(tmp_path / "p.fmu", platforms="x86_64-linux,aarch64-linux")
    err = capfd.readouterr().err.splitlines()
    said = [line for line in err if "built the FMU's binary for" in line]
    assert [s.split("]")[0] for s in said] == ["pdbfs: [1/2", "pdbfs: [2/2"], err
    assert {s.rsplit(" ", 1)[1] for s in said} == {"x86_64-linux", "aarch64-linux"}, err
