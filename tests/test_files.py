"""Files are written whole or not at all: a failure, or Ctrl-C, leaves the
destination as it was and no part file behind (pdbfs.files)."""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from pdbfs import files
from pdbfs.models import RIGS


def test_whole_replaces_only_on_success(tmp_path):
    dest = tmp_path / "out.csv"
    dest.write_text("old\n")
    with pytest.raises(RuntimeError):
        with files.whole(dest) as part:
            part.write_text("new, half")
            raise RuntimeError("stopped mid-write")
    assert dest.read_text() == "old\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]
    with files.whole(dest) as part:
        part.write_text("new\n")
    assert dest.read_text() == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_discard_removes_parts_under_way(tmp_path):
    with files.whole(tmp_path / "a.png") as part:
        part.write_bytes(b"x" * 100)
        assert part.suffix == ".png" and part.name.startswith(".")
        files.discard()
        assert not part.exists()
        part.write_bytes(b"y")          # the writer goes on; the rename still works
    assert (tmp_path / "a.png").read_bytes() == b"y"


def test_result_csv_failure_leaves_nothing(tmp_path, monkeypatch):
    """The disk fills up after the header: no file under either name."""
    import pdbfs.simulation.results.exports as result_module   # where Result.to_csv writes
    res = RIGS["paper"]().simulate(t_end=0.002)
    dest = tmp_path / "r.csv"
    writes = []

    class Full:
        def __init__(self, fh):
            self.fh = fh

        def write(self, text):
            writes.append(len(text))
            if len(writes) > 1:
                raise OSError("No space left on device")
            return self.fh.write(text)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.fh.close()

    monkeypatch.setattr(result_module, "open", lambda *a, **k: Full(open(*a, **k)), raising=False)
    with pytest.raises(OSError, match="No space"):
        res.to_csv(dest)
    assert len(writes) == 2 and list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    res.to_csv(dest)
    data = np.loadtxt(dest, delimiter=",", skiprows=1)
    assert data.shape[0] == res.t.size and np.allclose(data[:, 0], res.t)


def test_figure_without_suffix_uses_the_default_format(tmp_path):
    from matplotlib.figure import Figure
    fig = Figure()
    fig.add_subplot().plot([0, 1], [1, 0])
    path = files.save_figure(fig, tmp_path / "plot")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["plot"]


@pytest.mark.skipif(os.name != "posix", reason="SIGINT to a child process")
def test_ctrl_c_forced_exit_removes_the_part(tmp_path):
    """The main thread stuck mid-write (it swallows the KeyboardInterrupt):
    the watcher ends the process with 130 and the part is gone."""
    dest = tmp_path / "big.csv"
    code = textwrap.dedent(f"""
        import sys, time
        from pdbfs import files
        from pdbfs.cli import interrupt
        def stuck():
            while True:
                try:
                    time.sleep(0.05)
                except KeyboardInterrupt:
                    pass
        with interrupt.watching():
            with files.whole({str(dest)!r}) as part:
                part.write_text("half")
                # the one Ctrl-C swallowed wherever it lands (also between the loop's
                # lines, where a loaded machine may hold the process just then)
                try:
                    print("ready", flush=True)
                    stuck()
                except KeyboardInterrupt:
                    stuck()
    """)
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    assert p.stdout.readline().strip() == "ready"
    assert len(list(tmp_path.iterdir())) == 1          # the part, under its hidden name
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=20)
    assert p.returncode == 130 and time.monotonic() - t0 < 5
    assert err.strip() == "pdbfs: interrupted"
    assert list(tmp_path.iterdir()) == []
