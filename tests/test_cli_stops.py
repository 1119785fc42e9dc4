"""Commands that must end: no hang on a horizon a rounding error past the
summary's grid, and Ctrl-C stops every command promptly with one line and
exit status 130 (CasADi's solvers swallow SIGINT in the middle of a step)."""
import signal
import subprocess
import sys
import time

import pytest

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


def test_a_horizon_a_rounding_error_past_a_window_ends(tmp_path):
    """t_end = 0.06 + 1 ulp: the summary's last window was one point long (a
    NaN output time), and CVODE never came back."""
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "hydraulic-pulse",
                        "--set", "valve.t_open=0.01", "--set", "valve.t_close=0.0145",
                        "--t-end", "0.060000000000000005", "--out", str(tmp_path), "--json"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr and (tmp_path / "results.csv").exists()


def test_the_summary_grid_never_has_a_one_point_window():
    from pdbfs.models import RIGS
    import pdbfs.simulation.results.summary_run as S
    seen = []
    orig = S._integrate

    def spy(sim, grid, x, p, s, *rest):
        seen.append(len(grid))
        assert len(grid) >= 2 and grid[-1] > grid[0], f"a window of {len(grid)} point(s)"
        return orig(sim, grid, x, p, s, *rest)
    S._integrate = spy
    try:
        # the CasADi backend's summary: its own grid in windows (the compiled
        # backend's run summarises itself in the same call)
        res = RIGS["hydraulic-pulse"]().simulate(0.060000000000000005, n_out=11, params={
            "valve.t_open": 0.01, "valve.t_close": 0.0145}, backend="casadi")
        res.summary()
    finally:
        S._integrate = orig
    assert seen


def interrupted(args, tmp_path, after=4.0):
    p = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    time.sleep(after)
    assert p.poll() is None, "the command ended before Ctrl-C: make it longer"
    t0 = time.time()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    return p.returncode, err, time.time() - t0


KISTLER = str(ROOT / "docs" / "data" / "kistler_synthetic.csv")
LONG = {
    "simulate": ["simulate", "--t-end", "1000", "--out", "o"],
    "calibrate": ["calibrate", "--trace", KISTLER, "--free", "oil.k,seal.c,hammer.v0",
                  "--starts", "40", "--out", "o"],
    "design": ["design", "--peak", "150e6", "--duration", "0.009", "--free", "hammer.h,oil.k",
               "--t-end", "3", "--out", "o"],
    "design-map": ["design-map", "--x", "hammer.h=0.1:1.5", "--y", "oil.k=1e8:1e9", "--n", "300",
                   "--out", "o"],
    "sensitivity": ["sensitivity", "--range", "hammer.v0=2:4", "--range", "oil.k=1e8:1e9",
                    "--n", "65536"],
}


@pytest.mark.parametrize("command", sorted(LONG))
def test_ctrl_c_stops_every_command_with_one_line(command, tmp_path):
    status, err, took = interrupted(LONG[command], tmp_path)
    assert status == 130, err
    lines = err.strip().splitlines()
    assert lines == ["pdbfs: interrupted"], err
    assert took < 5.0, f"{command} took {took:.1f} s to stop"


def test_the_watch_ends_with_the_command():
    """main() run in a process of its own (as tests and scripts do) leaves
    SIGINT, the wakeup fd and the threads as it found them."""
    import signal
    import threading
    from pdbfs.cli import main
    before = signal.getsignal(signal.SIGINT), threading.active_count()
    assert main(["params", "--rig", "paper", "--json"]) == 0
    assert main(["params", "--rig", "drop", "--json"]) == 0
    assert (signal.getsignal(signal.SIGINT), threading.active_count()) == before
    assert signal.set_wakeup_fd(-1) == -1


def test_ctrl_c_stops_the_workbench_with_status_130(tmp_path):
    """`pdbfs app`: its web server returns quietly from a Ctrl-C (status 0 before);
    it says so in one line and exits 130, as every other command. The signal
    goes to the process group, as a terminal's Ctrl-C does."""
    import os
    import socket
    pytest.importorskip("dash")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    p = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--port", str(port)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path,
                         start_new_session=True)
    try:
        ready = p.stdout.readline()                      # once it serves
        assert "Ctrl-C stops it" in ready, p.stderr.read() if p.poll() is not None else ready
        time.sleep(1.0)                                  # serving, not starting
        t0 = time.time()
        os.killpg(p.pid, signal.SIGINT)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
    assert p.returncode == 130, err
    assert err.strip().splitlines() == ["pdbfs: interrupted"], err
    assert time.time() - t0 < 5.0
