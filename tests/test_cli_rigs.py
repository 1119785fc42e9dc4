"""--rig names a user's own rig (FILE.py:NAME, MODULE:NAME) in every
command and in the workbench, each failure to load it one line naming the
culprit; `pdbfs rigs` lists the rigs with their inputs; the shipped valve
plant takes its command from a file, in simulate, sweep and calibrate."""
import argparse
import json
import subprocess
import sys

import numpy as np
import pytest

import pdbfs
from pdbfs.cli import build_parser, main
from pdbfs.models import RIGS

from cli_support import cli, one_line

OSCILLATOR = '''
import pdbfs
from pdbfs.components import Fixed, Mass, Spring


class Oscillator(pdbfs.Rig):
    """A mass on a spring to the frame, started moving."""

    name = "oscillator"

    def declare(self):
        self.frame = Fixed()
        self.mass = Mass(m=2.0, v0=1.0)
        self.spring = Spring(k=8e4)
        self.connect(self.mass.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.frame.flange)


def stiff():
    rig = Oscillator()
    rig.spring.bind("k", 3.2e5)
    return rig


def broken():
    raise ValueError("no such spring")


def wrong():
    return 42


answer = 42
built = Oscillator()
'''


@pytest.fixture
def rigs_folder(tmp_path):
    (tmp_path / "oscillator.py").write_text(OSCILLATOR)
    return tmp_path


# -- a rig of one's own -----------------------------------------------------------------
def test_a_users_rig_runs_through_the_commands_to_its_closed_forms(rigs_folder):
    """m = 2 kg on k = 8e4 N/m: omega = sqrt(k/m) = 200 rad/s, started at
    1 m/s its amplitude is v0/omega; the factory's k = 3.2e5 gives 400."""
    r = cli("modes", "--rig", "oscillator.py:Oscillator", "--json", cwd=rigs_folder)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["modes"][0]["omega"] == pytest.approx(200.0, rel=1e-12)
    for spec in ("oscillator.py:stiff", "oscillator:stiff"):      # a file, a module here
        r = cli("modes", "--rig", spec, "--json", cwd=rigs_folder)
        assert r.returncode == 0, r.stderr
        assert json.loads(r.stdout)["modes"][0]["omega"] == pytest.approx(400.0, rel=1e-12)
    r = cli("linearize", "--rig", "oscillator.py", cwd=rigs_folder)   # its one Rig class
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["A"] == [[0.0, 1.0], [-4e4, 0.0]]
    r = cli("simulate", "--rig", "oscillator.py:Oscillator", "--t-end", "0.02", "--out", "run",
            cwd=rigs_folder)
    assert r.returncode == 0, r.stderr
    import pandas as pd
    s = pd.read_csv(rigs_folder / "run" / "results.csv").filter(like="mass.s").iloc[:, 0]
    assert np.max(np.abs(s)) == pytest.approx(1.0 / 200.0, rel=1e-5)
    r = cli("params", "--rig", "oscillator.py:Oscillator", "--json", cwd=rigs_folder)
    assert {p["name"]: p["value"] for p in json.loads(r.stdout)}["spring.k"] == 8e4
    r = cli("sweep", "--rig", "oscillator.py:Oscillator", "--set", "spring.k=8e4,3.2e5",
            "--quiet", "--json", cwd=rigs_folder)
    assert r.returncode == 0 and json.loads(r.stdout)["failed"] == 0, r.stderr


def _with_required(name: str) -> list[str]:
    return {"calibrate": ["--trace", "t.csv", "--free", "a"], "design": ["--free", "a"],
            "design-map": ["--x", "a=1:2", "--y", "b=1:2"],
            "campaign": ["--blows", "2", "--period", "1"]}.get(name, [])


COMMANDS = [n for n, p in next(a for a in build_parser()._actions
                               if isinstance(a, argparse._SubParsersAction)).choices.items()
            if any("--rig" in a.option_strings for a in p._actions)]


@pytest.mark.parametrize("command", [c for c in COMMANDS if c != "app"])
def test_every_command_with_rig_loads_a_users_rig_first(command, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status = main([command, "--rig", "missing.py:Mine", *_with_required(command)])
    err = capsys.readouterr().err.strip()
    assert status == 2 and err == "pdbfs: error: --rig missing.py:Mine: no such file missing.py"
    assert list(tmp_path.iterdir()) == []
    assert {"simulate", "params", "export-fmu", "modes", "linearize", "sweep", "sensitivity",
            "calibrate", "design", "design-map", "rigs"} <= set(COMMANDS)


@pytest.mark.parametrize("spec,text,words", [
    ("nowhere.py:Oscillator", None, ["--rig nowhere.py:Oscillator", "no such file nowhere.py"]),
    ("bad.py:X", "import pdbfs\nclass X(pdbfs.Rig:\n    pass\n",
     ["--rig bad.py:X", "bad.py line 2", "invalid syntax"]),
    ("needs.py:X", "import not_a_module_of_anyone\n",
     ["ModuleNotFoundError", "not_a_module_of_anyone", "needs.py line 1"]),
    ("oscillator.py:Nope", None, ["oscillator.py has no 'Nope'", "its Rig classes: Oscillator"]),
    ("oscillator.py:answer", None, ["answer is the int 42", "not a Rig class"]),
    ("oscillator.py:Spring", None, ["Spring is the class Spring, not a Rig subclass"]),
    ("oscillator.py:built", None, ["built is a rig", "name its class (Oscillator)"]),
    ("oscillator.py:broken", None, ["broken() failed: ValueError: no such spring",
                                    "oscillator.py line 26"]),
    ("oscillator.py:wrong", None, ["wrong() returned the int 42, not a rig"]),
    ("neg.py", "import pdbfs\nfrom pdbfs.components import Mass\nclass R(pdbfs.Rig):\n"
     "    def declare(self):\n        self.a = Mass(m=-1.0)\n",
     ["R() failed: Mass.m = -1 kg: must be > 0", "neg.py line 5"]),
    ("two.py", "import pdbfs\nclass A(pdbfs.Rig):\n    pass\nclass B(pdbfs.Rig):\n    pass\n",
     ["name the rig as FILE.py:NAME (it defines A, B)"]),
    ("no_module_here:Rig", None, ["no module named 'no_module_here'"]),
    ("papr", None, ["unknown rig 'papr'", "hydraulic-pulse-plant", "FILE.py:NAME"]),
], ids=["no file", "syntax", "import", "no name", "not callable", "not a rig class",
        "an instance", "raises", "returns no rig", "declare raises", "two classes", "no module",
        "unknown name"])
def test_a_rig_that_cannot_be_loaded_is_one_line_naming_it(spec, text, words, rigs_folder):
    if text is not None:
        (rigs_folder / spec.split(":")[0]).write_text(text)
    before = sorted(p.name for p in rigs_folder.iterdir())
    one_line(cli("simulate", "--rig", spec, "--out", "o", cwd=rigs_folder), *words)
    assert sorted(p.name for p in rigs_folder.iterdir() if p.name != "__pycache__") == \
        [b for b in before if b != "__pycache__"]


def test_the_workbench_offers_the_users_rig_it_was_started_with(rigs_folder, monkeypatch):
    pytest.importorskip("dash")
    from pdbfs.app.workbench import offer, rig_names, workbench
    from pdbfs.errors import ParameterError
    monkeypatch.chdir(rigs_folder)
    with pytest.raises(ParameterError, match="unknown rig 'oscillator.py:stiff'"):
        workbench("oscillator.py:stiff")      # a name from a page never imports a file
    offer("oscillator.py:stiff")
    wb = workbench("oscillator.py:stiff")
    assert rig_names()[:len(RIGS)] == list(RIGS) and "oscillator.py:stiff" in rig_names()
    assert {c.name for c in wb.controls} >= {"mass.m", "spring.k"}
    assert wb.file_name == "oscillator"
    k = next(c for c in wb.controls if c.name == "spring.k")
    assert k.default == 3.2e5


def test_pdbfs_app_serves_a_users_rig(rigs_folder):
    pytest.importorskip("dash")
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--rig", "oscillator.py",
                             "--port", str(port)], cwd=rigs_folder, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert "workbench of rig oscillator.py at http://127.0.0.1:" in line, proc.stderr.read()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    one_line(cli("app", "--rig", "oscillator.py:answer", "--port", str(port), cwd=rigs_folder),
             "answer is the int 42")


# -- the listing ------------------------------------------------------------------------
def test_pdbfs_rigs_lists_every_rig_with_its_inputs(tmp_path):
    r = cli("rigs", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    entries = json.loads(r.stdout)
    assert [e["name"] for e in entries] == list(RIGS)
    for e in entries:
        assert e["description"] and "\n" not in e["description"], e["name"]
        assert e["outputs"] and all(o["unit"] and o["description"] for o in e["outputs"])
    plant = next(e for e in entries if e["name"] == "hydraulic-pulse-plant")
    assert plant["inputs"] == [{"name": "opening", "unit": "1", "start": 0.0,
                                "description": "Commanded valve opening, 0 closed to 1 open"}]
    assert "sensor.y" in [o["name"] for o in plant["outputs"]]
    assert not [e["name"] for e in entries if e["inputs"]
                and any(not (u["unit"] and u["description"]) for u in e["inputs"])]
    r = cli("rigs", cwd=tmp_path)
    assert r.returncode == 0 and "opening [1] Commanded valve opening" in r.stdout
    assert list(tmp_path.iterdir()) == []


# -- the valve plant and its input --------------------------------------------------------
def _loop_command(folder):
    """The closed loop's valve command, every microsecond, as a CSV file."""
    from pdbfs.models import hydraulic_pulse_pid_rig
    loop = hydraulic_pulse_pid_rig().simulate(0.02, n_out=20001)
    path = folder / "command.csv"
    np.savetxt(path, np.column_stack([loop.t, loop["pid.y"]]), delimiter=",",
               header="time [s],opening", comments="", fmt="%.17g")
    return loop, path


def test_the_plant_driven_by_the_loops_command_gives_the_loops_pulse(tmp_path):
    """Plant and controller in one rig, or the plant alone replaying the
    controller's command: the same pressure (the command joined by straight
    lines between samples 1 us apart: agreement to about 1e-7)."""
    loop, path = _loop_command(tmp_path)
    r = cli("simulate", "--rig", "hydraulic-pulse-plant", "--input", f"opening={path.name}",
            "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    got, want = json.loads(r.stdout), loop.summary()
    assert got["peak_pressure"] == pytest.approx(want["peak_pressure"], rel=1e-6)
    assert got["time_of_peak"] == pytest.approx(want["time_of_peak"], rel=1e-6)
    assert got["pulse_duration"] == pytest.approx(want["pulse_duration"], rel=1e-6)


def test_sweep_and_calibrate_take_the_plants_input(tmp_path):
    command = str(pdbfs.example_data("valve_opening.csv"))
    r = cli("simulate", "--rig", "hydraulic-pulse-plant", "--input", f"opening={command}",
            "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    alone = json.loads(r.stdout)["peak_pressure"]
    r = cli("sweep", "--rig", "hydraulic-pulse-plant", "--input", f"opening={command}",
            "--set", "valve.A=4e-5,8e-5", "--quiet", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    peaks = [p["summary"]["peak_pressure"] for p in json.loads(r.stdout)["points"]]
    assert peaks[1] == pytest.approx(alone, rel=1e-9)      # valve.A = 8e-5 is the rig's own
    assert 0.3 * peaks[1] < peaks[0] < 0.7 * peaks[1]     # half the valve, about half the rise
    # a "measurement" at K = 1.2 GPa (the rig's 1.5 GPa the fit's start), fitted back
    from pdbfs.cli.inputs import read_input
    from pdbfs.models import pulse_plant_rig
    t = np.linspace(0.0, 0.02, 401)
    p = pulse_plant_rig().simulate(0.02, t_out=t, params={"chamber.K": 1.2e9},
                                   inputs={"opening": read_input(command, "opening", "1")})
    np.savetxt(tmp_path / "measured.csv", np.column_stack([t, p["chamber.p"]]), delimiter=",",
               header="time [s],pressure [Pa]", comments="", fmt="%.17g")
    r = cli("calibrate", "--rig", "hydraulic-pulse-plant", "--input", f"opening={command}",
            "--trace", "measured.csv", "--free", "chamber.K", "--starts", "1", "--json",
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["params"]["chamber.K"] == pytest.approx(1.2e9, rel=1e-6)
