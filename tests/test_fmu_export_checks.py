"""What export_fmu refuses before any work, in one line (a bad default
experiment, an empty or folder name, in the API and on the command line),
and what an interrupted export leaves behind: nothing (no platform's build
starts after it, and its build folder goes, even when the process is ended
before its own cleanup)."""
import math
import subprocess
import sys
import tempfile
import threading

import pytest

import fmu_support as T
from pdbfs import files
from pdbfs.errors import ExportError
from pdbfs.fmu import export as E

BAD_EXPERIMENTS = [({"stop_time": math.nan}, "stop_time = nan"), ({"stop_time": -1.0}, "stop_time = -1.0"),
                   ({"stop_time": "1"}, "stop_time = '1'"), ({"step_size": -1e-3}, "step_size = -0.001"),
                   ({"step_size": 1.0}, "step_size = 1.0"), ({"step_size": math.inf}, "step_size = inf"),
                   ({"tolerance": -1}, "tolerance = -1"), ({"tolerance": math.nan}, "tolerance = nan"),
                   ({"tolerance": 0.5}, "tolerance = 0.5"), ({"tolerance": True}, "tolerance = True")]


@pytest.mark.parametrize("kw, culprit", BAD_EXPERIMENTS, ids=[c for _, c in BAD_EXPERIMENTS])
def test_a_bad_default_experiment_is_refused_before_any_work(kw, culprit, tmp_path, monkeypatch):
    """NaN and negatives never reach modelDescription.xml (before: written
    there as given; a NaN tolerance failed late, inside the compiler)."""
    dae, rig = T.built_model("paper")
    def no_work(*a, **k):
        raise AssertionError("work was done")
    monkeypatch.setattr(E, "generate", no_work)
    for call in (lambda: E.export_fmu(dae, tmp_path / "a.fmu", **kw),
                 lambda: rig.export_fmu(tmp_path / "a.fmu", **kw)):
        with pytest.raises(ExportError) as err:
            call()
        assert str(err.value).startswith(culprit) and "\n" not in str(err.value)
    assert not list(tmp_path.iterdir())


def test_an_empty_name_is_not_called_a_folder(tmp_path):
    dae, rig = T.built_model("paper")
    for call in (lambda: E.export_fmu(dae, ""), lambda: rig.export_fmu("")):
        with pytest.raises(ExportError, match="file name is empty"):
            call()
    with pytest.raises(ExportError, match="is a folder"):
        rig.export_fmu(tmp_path)


def _cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True, text=True,
                          timeout=120, cwd=cwd)


def test_the_commands_name_an_empty_fmu_name_and_a_folder_given_as_an_fmu(tmp_path):
    r = _cli("export-fmu", "-o", "", cwd=tmp_path)
    assert r.returncode == 2 and "file name is empty" in r.stderr and "folder" not in r.stderr, r.stderr
    r = _cli("export-ssp", "--fmu", "p=.", "-o", "s.ssp", cwd=tmp_path)
    assert r.returncode == 2 and ". is a folder, not an FMU file" in r.stderr and "no such" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not list(tmp_path.iterdir())


def test_an_interrupted_build_starts_no_other_platform_and_leaves_no_folder(tmp_path, monkeypatch):
    """Ctrl-C while the first platform builds: the platforms queued behind
    it are not built, and the build folder goes."""
    dae, _ = T.built_model("paper")
    host = E.platform_sundials(E.resolve_platforms(None)[0])
    monkeypatch.setattr(E, "_platform_sundials", lambda plats: {n: host for n in plats})
    started, lock = [], threading.Lock()

    def build(name, *args, **kw):
        with lock:
            started.append(name)
            first = len(started) == 1
        if first:
            raise KeyboardInterrupt
        threading.Event().wait(0.5)
        return args[2]
    monkeypatch.setattr(E, "build_binary", build)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with pytest.raises(KeyboardInterrupt):
        E.export_fmu(dae, tmp_path / "out" / "a.fmu", platforms="all")
    assert len(started) <= 2, started                 # two workers: the first and the one beside it
    assert [p.name for p in tmp_path.iterdir()] == ["out"] and not list((tmp_path / "out").iterdir())


def test_ctrl_c_during_the_compiler_leaves_no_build_folder(tmp_path):
    """SIGINT to `pdbfs export-fmu` while zig compiles (the compiler not
    signalled, as from `kill -INT` or an IDE's stop button): the CLI ends
    the process after its grace second, and the build folder goes with it
    (before, it stayed in the temporary directory)."""
    import os
    import signal
    import time
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = dict(os.environ, TMPDIR=str(tmp))
    p = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "export-fmu", "-o", str(tmp_path / "a.fmu")],
                         cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    try:
        deadline = time.monotonic() + 120
        while not list(tmp.glob("pdbfs-fmu-*/build")) and p.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        assert p.poll() is None, p.communicate()
        p.send_signal(signal.SIGINT)
        _, err = p.communicate(timeout=60)
        assert p.returncode == 130 and "interrupted" in err, err
        while time.monotonic() < deadline:        # the compiler, left running, ends too
            try:
                os.killpg(p.pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.1)
    finally:
        if p.poll() is None:
            p.kill()
    assert not list(tmp.iterdir()) and not (tmp_path / "a.fmu").exists()


def test_a_forced_exit_removes_the_build_folder(tmp_path, monkeypatch):
    """The CLI's Ctrl-C watcher ends a process that does not stop within a
    second (files.discard, then os._exit): the build folder goes too."""
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    with files.scratch_folder("pdbfs-fmu-") as folder:
        (folder / "sources").mkdir()
        files.discard()
        assert not folder.exists()
    assert not list(tmp_path.iterdir())
