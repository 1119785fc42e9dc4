"""Commands that worked for minutes without a word (or grew to gigabytes):
each is refused up front in one line, or bounded and tells how far it got."""
import io
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
KISTLER = ROOT / "docs" / "data" / "kistler_synthetic.csv"


def run(*args, cwd, timeout=600):
    """`pdbfs ARGS`: (return code, stdout, stderr); killed after ``timeout`` s."""
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", *args], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        raise
    return proc.returncode, out, err


def on_terminal(*args, cwd, timeout=900):
    """`pdbfs ARGS` with stderr on a terminal (a pty), as a user runs it: (return
    code, stdout, the lines stderr showed as it went (each rewrite of the line
    one entry), peak resident memory in bytes (VmHWM: this child's own since
    its exec; ru_maxrss also holds the parent's at the fork, a test worker's
    gigabyte))."""
    import pty
    import tempfile
    import threading
    hwm = Path(tempfile.mkdtemp()) / "hwm"
    code = ("import atexit, sys\n"
            "def hwm():\n"
            "    with open('/proc/self/status') as st, open(%r, 'w') as fh:\n"
            "        fh.write(next(ln.split()[1] for ln in st if ln.startswith('VmHWM:')))\n"
            "atexit.register(hwm)\n"
            "from pdbfs.cli import main\n"
            "sys.exit(main(%r))\n" % (str(hwm), list(args)))
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=cwd,
                            stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    chunks = []

    def drain():
        while True:
            try:
                data = os.read(master, 65536)
            except OSError:              # EIO: the child closed the terminal
                return
            if not data:
                return
            chunks.append(data)
    reader = threading.Thread(target=drain, daemon=True)
    reader.start()
    timer = threading.Timer(timeout, proc.kill)
    timer.start()
    out = proc.stdout.read()
    _, status = os.waitpid(proc.pid, 0)
    timer.cancel()
    reader.join(10)
    os.close(master)
    proc.returncode = os.waitstatus_to_exitcode(status)
    shown = b"".join(chunks).decode().replace("\033[K", "").replace("\r\n", "\n")
    lines = [ln for part in shown.split("\n") for ln in part.split("\r") if ln]
    return proc.returncode, out, lines, 1024.0 * float(hwm.read_text())


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="VmHWM in /proc as Linux has it")
def test_many_output_points_are_written_in_bounded_memory_with_progress(tmp_path):
    """400 000 points held 2 GB while results.csv was formatted (5.4 GB at a
    million, 3.3 GB and growing at ten million), with no word for minutes."""
    n = 400_000
    code, out, lines, rss = on_terminal("simulate", "--n-out", str(n), "--out", "o",
                                        cwd=tmp_path)
    assert code == 0, lines
    assert rss < 700e6, f"peak memory {rss / 1e6:.0f} MB"
    assert lines and all(re.fullmatch(r"pdbfs: writing o/results\.csv: \d+ of 400000 rows "
                                      r"\(\d+ %\).* so far", ln) for ln in lines), lines
    csv = tmp_path / "o" / "results.csv"
    with open(csv) as fh:
        header = fh.readline().rstrip("\r\n").split(",")
        first = np.array(fh.readline().split(","), dtype=float)
    assert header[0] == "time [s]" and len(first) == len(header)
    # every row written: the file ends with the last output time
    with open(csv, "rb") as fh:
        fh.seek(-4096, 2)
        last = fh.read().decode().splitlines()[-1].split(",")
    assert float(last[0]) == 0.02 and len(last) == len(header)
    assert (tmp_path / "o" / "results.png").stat().st_size > 10_000


def test_a_results_csv_larger_than_the_disk_is_refused_before_the_run(tmp_path, monkeypatch,
                                                                     capsys):
    import shutil

    from pdbfs.cli import main
    from pdbfs.simulation.run.simulator import Simulator

    class Usage:
        total, used, free = 10 ** 9, 10 ** 9 - 10 ** 6, 10 ** 6

    def no_run(*a, **k):
        raise AssertionError("the run started before the disk was looked at")
    monkeypatch.setattr(shutil, "disk_usage", lambda path: Usage)
    monkeypatch.setattr(Simulator, "run", no_run)
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", "--n-out", "200000", "--out", "o"]) == 2
    err = capsys.readouterr().err.strip()
    assert re.fullmatch(r"pdbfs: error: --n-out 200000: o/results\.csv would take about "
                        r"[0-9.]+ MB, and 1 MB are free on its disk; ask for fewer output "
                        r"points", err), err
    assert not (tmp_path / "o").exists()


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_says_nothing_at_first_then_rewrites_its_line_and_clears_it():
    from pdbfs.cli.progress import AFTER, EVERY, Progress
    now = [0.0]
    buf = Terminal()
    with Progress("calibrating", "simulations", stream=buf, clock=lambda: now[0]) as p:
        for k in range(1, 161):
            now[0] = 0.125 * k             # (exact binary fractions)
            p(k)
    shown = buf.getvalue().split("\r")[1:]
    # from AFTER s on, the line once every EVERY s of the 20 s; then cleared
    assert len(shown) == 1 + int((20.0 - AFTER) // EVERY) + 1 and shown[-1] == "\033[K"
    assert shown[0] == f"pdbfs: calibrating: {round(AFTER / 0.125)} simulations, 2 s so far\033[K"
    buf = Terminal()
    p = Progress("writing x.csv", "rows", stream=buf, clock=lambda: now[0])
    now[0] += 30.0
    p(250, 1000)
    assert buf.getvalue() == "\rpdbfs: writing x.csv: 250 of 1000 rows (25 %), about 90 s to " \
                             "go, 30 s so far\033[K"
    buf = io.StringIO()                   # no terminal: no word
    p = Progress("writing x.csv", "rows", stream=buf, clock=lambda: now[0])
    now[0] += 30.0
    p(250, 1000)
    assert buf.getvalue() == ""


def test_a_peak_after_the_pulse_has_ended_is_refused_at_once(tmp_path):
    """It ran for over 15 minutes (a 2 s horizon at 5 us, with sensitivities)."""
    t0 = time.time()
    code, out, err = run("design", "--peak", "1.5e8", "--duration", "0.001", "--time-of-peak",
                         "0.5", "--free", "hammer.h,oil.k", cwd=tmp_path, timeout=180)
    assert code == 2 and out == "", (code, out, err)
    line = err.strip()
    assert "\n" not in line and line.startswith("pdbfs: error: design targets: time_of_peak = "
                                                "0.5 s comes after a pulse of pulse_duration = "
                                                "0.001 s has ended"), line
    peak_by = float(re.search(r"peaks by ([0-9.e-]+) s", line).group(1))
    # the rig's own peak at the widest bounds: a factor 10 softer oil, a factor 10 lower drop
    assert 0.005 < peak_by < 0.05, line
    assert time.time() - t0 < 120


def test_a_peak_a_gap_can_delay_is_not_refused():
    """A gap opened at the start delays the blow: a late peak is then reachable."""
    from pdbfs.models import paper_rig
    from pdbfs.simulation import Simulator
    from pdbfs.studies.fitting.design import check_peak_in_pulse
    from pdbfs.studies.fitting.free_parameters import DESIGN_RANGE, rig_unknowns
    rig = paper_rig()
    unknowns, _ = rig_unknowns(Simulator.of(rig), ["contact.gap", "oil.k"], factor=DESIGN_RANGE,
                               bounds={"contact.gap": (0.0, 1.0)})
    goals = {"time_of_peak": 0.3, "pulse_duration": 0.001}
    check_peak_in_pulse(rig, unknowns, {}, goals, 1.2)      # 1 m at 2.73 m/s: 0.37 s
    with pytest.raises(Exception, match="comes after a pulse"):
        check_peak_in_pulse(rig, unknowns, {}, {**goals, "time_of_peak": 1.0}, 4.0)


def test_a_long_calibration_tells_how_far_it_got(tmp_path):
    """The paper's trace stretched to 0.2 s: minutes of fitting without a word."""
    d = np.loadtxt(KISTLER, delimiter=",", skiprows=1)
    d[:, 0] *= 0.2 / d[-1, 0]
    np.savetxt(tmp_path / "stretched.csv", d, delimiter=",", header="time_s,pressure_Pa",
               comments="")
    code, out, lines, _ = on_terminal("calibrate", "--trace", "stretched.csv", "--free",
                                      "oil.k", cwd=tmp_path)
    assert code == 0, lines
    assert lines and all(re.fullmatch(r"pdbfs: calibrating: \d+ simulations, \d+ (s|min) so far",
                                      ln) for ln in lines), lines
    assert "oil.k" in out and "RMS residual" in out
    # where stderr is no terminal (a log, a pipe), nothing but the result and warnings
    code, out, err = run("design", "--peak", "1.2e8", "--free", "oil.k", cwd=tmp_path)
    assert code == 0 and "designing" not in err, err
