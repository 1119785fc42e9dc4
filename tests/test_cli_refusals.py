"""Inputs refused with one line and exit status 2, before the work they would
waste: each once ended in a traceback, a hang or a memory blow-up."""
import socket
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
KISTLER = ROOT / "docs" / "data" / "kistler_synthetic.csv"


def cli(*args, cwd, env=None, timeout=120):
    import os
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=timeout, cwd=cwd,
                          env=None if env is None else {**os.environ, **env})


def one_line(r, *words):
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error: "), r.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]


def test_a_drop_height_on_the_drop_rig_names_its_own_height(tmp_path):
    """hammer.h stood for hammer.v0 = 0 there: its scaling divided by 0."""
    one_line(cli("calibrate", "--rig", "drop", "--free", "hammer.h", "--trace", str(KISTLER),
                 cwd=tmp_path), "hammer.h", "drop height of its own, h")
    one_line(cli("design", "--rig", "drop", "--peak", "120e6", "--free", "hammer.h", cwd=tmp_path),
             "hammer.h", "drop height of its own, h")


def test_a_drop_height_at_zero_is_refused(tmp_path):
    one_line(cli("design", "--peak", "120e6", "--free", "hammer.h", "--bounds", "hammer.h=0:1",
                 cwd=tmp_path), "hammer.h", "above 0 m")
    one_line(cli("design", "--peak", "120e6", "--free", "hammer.h", "--set", "hammer.v0=0",
                 cwd=tmp_path), "hammer.h")


def test_a_height_and_its_speed_are_one_setting(tmp_path):
    one_line(cli("design-map", "--x", "hammer.h=0.1:1", "--y", "hammer.v0=1:3", "--out", "o",
                 cwd=tmp_path), "hammer.h and hammer.v0 are the same setting")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args,what", [
    (["design-map", "--x", "hammer.h=0.1:1.5", "--y", "oil.k=1e8:1e9", "--n", "100000",
      "--out", "o"], "100000 x 100000 points"),
    (["simulate", "--n-out", "100000000", "--out", "o"], "100000000 output points"),
])
def test_sizes_that_cannot_fit_are_refused_up_front(args, what, tmp_path):
    import psutil
    t0 = time.time()
    line = one_line(cli(*args, cwd=tmp_path), what, "of memory", "are available")
    assert time.time() - t0 < 30 and "np.float64" not in line
    need = float(line.split("about ")[1].split()[0]) * {"GB": 1e9, "TB": 1e12}[
        line.split("about ")[1].split()[1]]
    assert need > 0.8 * psutil.virtual_memory().available
    assert not (tmp_path / "o").exists()


def test_a_sweep_held_in_memory_that_cannot_fit_is_refused():
    from pdbfs.errors import ParameterError
    from pdbfs.studies import sweep
    from pdbfs.studies.sweeps.sampling import Sample
    # Monte Carlo points are drawn in blocks: the sweep's own table is what cannot fit
    # (a Latin hypercube this size is refused by the sampler first: test_ignored_options)
    with pytest.raises(ParameterError, match="10000000000 points in memory .* are available; "
                       "give out="):
        sweep("paper", Sample("mc", 10 ** 10, ranges={"hammer.v0": (2.0, 3.0)}))


def test_an_unusable_cache_folder_is_named_with_its_variable(tmp_path):
    line = one_line(cli("export-fmu", "-o", "x.fmu", cwd=tmp_path,
                        env={"XDG_CACHE_HOME": "/proc/nonexistent"}), "/proc/nonexistent/pdbfs",
                    "XDG_CACHE_HOME")
    assert not (tmp_path / "x.fmu").exists(), line


def test_a_trace_stamped_long_after_the_run_says_what_to_subtract(tmp_path):
    d = np.loadtxt(KISTLER, delimiter=",", skiprows=1)
    d = d[d[:, 0] <= 0.02]
    d[:, 0] += 1000.0
    late = tmp_path / "late.csv"
    np.savetxt(late, d, delimiter=",", header="time_s,pressure_Pa", comments="")
    t0 = time.time()
    one_line(cli("calibrate", "--trace", str(late), "--free", "oil.k", cwd=tmp_path),
             "late.csv", "start at t = 1000 s", "subtract 1000 s")
    one_line(cli("design", "--target", str(late), "--free", "oil.k", cwd=tmp_path),
             "late.csv", "subtract 1000 s")
    assert time.time() - t0 < 60


def listener(reply: bytes):
    """A plain TCP server on 127.0.0.1 that is not a Dask scheduler."""
    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen()
    held = []

    def serve():
        while True:
            try:
                conn, _ = srv.accept()
            except OSError:
                return
            held.append(conn)
            if reply:
                conn.sendall(reply)
    threading.Thread(target=serve, daemon=True).start()
    return srv


@pytest.mark.parametrize("reply", [b"", b"HTTP/1.1 200 OK\r\nContent-Length: 0\r\n\r\n"],
                         ids=["silent", "http"])
def test_dask_at_a_server_that_is_no_scheduler(reply, tmp_path):
    srv = listener(reply)
    address = f"tcp://127.0.0.1:{srv.getsockname()[1]}"
    try:
        t0 = time.time()
        r = cli("sweep", "--set", "hammer.v0=2,3", "--dask", address, "--no-plot", cwd=tmp_path,
                timeout=60)
        took = time.time() - t0
    finally:
        srv.close()
    one_line(r, f"cannot reach a Dask scheduler at '{address}'")
    assert took < 5.0 + 10.0       # 5 s as README says, plus starting Python and pdbfs
