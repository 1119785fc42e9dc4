"""What the commands print is what a user can act on: an address a browser
opens, the time a failed run really reached, a count printed as a number."""
import os
import re
import subprocess
import sys
import time
import urllib.request

import pytest


def free_port() -> int:
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cli(*args, cwd, timeout=300):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=timeout, cwd=cwd)


def _ipv6_loopback() -> bool:
    import socket
    try:
        with socket.socket(socket.AF_INET6) as s:
            s.bind(("::1", 0))
        return True
    except OSError:
        return False


@pytest.mark.skipif(not _ipv6_loopback(), reason="no IPv6 loopback on this machine")
@pytest.mark.skipif(__import__("importlib").util.find_spec("dash") is None, reason="no dash")
@pytest.mark.parametrize("host", ["::1", "[::1]"])
def test_app_on_ipv6_prints_an_address_a_browser_opens(host, tmp_path):
    port = free_port()
    proc = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "app", "--host", host,
                             "--port", str(port)], cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            env={**os.environ, "TMPDIR": str(tmp_path)})
    try:
        line = proc.stdout.readline()
        url = f"http://[::1]:{port}/"
        assert url in line, line
        page, t0 = None, time.time()
        while page is None and time.time() - t0 < 60:     # the address, as printed, answers
            try:
                page = urllib.request.urlopen(url, timeout=5).read().decode()
            except OSError:
                time.sleep(0.3)
        assert page is not None and "pdbfs" in page
    finally:
        proc.terminate()
        proc.wait(20)


def test_page_url_brackets_ipv6_only():
    from pdbfs.app.server import page_url
    assert page_url("::1", 8050) == "http://[::1]:8050/"
    assert page_url("fe80::1", 80) == "http://[fe80::1]:80/"
    assert page_url("127.0.0.1", 8050) == "http://127.0.0.1:8050/"
    assert page_url("localhost", 1) == "http://localhost:1/"


def test_summary_prints_a_count_and_a_ratio_without_the_unit_1(tmp_path):
    r = cli("simulate", "--rig", "drop", "--out", "o", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = {ln.split()[0]: ln for ln in r.stdout.splitlines() if ln.startswith("  ")}
    count = lines["impact_count"]
    assert re.fullmatch(r"  impact_count +\d+", count), count
    ratio = lines["restitution_coefficient"]
    assert re.fullmatch(r"  restitution_coefficient +[0-9.]+", ratio), ratio
    # the numbers stay in one column: they end where the peak pressure's number ends
    peak = lines["peak_pressure"]
    assert peak.endswith(" Pa")
    assert len(count) == len(ratio) == len(peak) - len(" Pa")


@pytest.mark.parametrize("method", ["erk", "adams", "bdf"])
def test_a_failed_run_reports_the_time_its_solver_reached(method):
    """The compiled run reported its last output time (0 s: the first output
    point lay 50 s ahead) though the solver had integrated the whole pulse."""
    from pdbfs.errors import SolverError
    from pdbfs.models import paper_rig
    rig, budget = paper_rig(), 20000
    with pytest.raises(SolverError) as err:
        rig.simulate(100.0, n_out=3, method=method, backend="c", max_num_steps=budget)
    msg = str(err.value)
    t_r = float(re.search(r"failed after t = ([0-9.e+-]+) s \(of 100 s\)", msg).group(1))
    assert 0.02 < t_r < 50.0, msg          # past the pulse (over by 12 ms), before the output
    assert "too many steps" in msg and ("try method='bdf'" in msg) == (method != "bdf"), msg
    # the time is where the step budget ran out: a run a little shorter fits in it,
    # a little longer does not
    rig.simulate(0.9 * t_r, n_out=2, method=method, backend="c", max_num_steps=budget)
    with pytest.raises(SolverError, match="too many steps"):
        rig.simulate(1.1 * t_r, n_out=2, method=method, backend="c", max_num_steps=budget)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS as Linux has it")
def test_a_run_out_of_memory_says_so_and_where(tmp_path):
    """It said "CVODE failed (explicit Runge-Kutta: out of memory)" at t = 0 s
    and suggested method='bdf'."""
    import resource

    def limit():        # 3 GB of address space: the run's record of its steps outgrows it
        resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--t-end", "1e4",
                        "--method", "erk", "--out", "o"], capture_output=True, text=True,
                       timeout=600, cwd=tmp_path, preexec_fn=limit)
    assert r.returncode == 2, r.stderr[-2000:]
    line = r.stderr.strip()
    m = re.fullmatch(r"pdbfs: error: rig pdbfs_paper: the run ran out of memory after "
                     r"t = ([0-9.e+-]+) s \(of 10000 s, \d+ steps\): .*shorter t_end", line)
    assert m and float(m.group(1)) > 0.02, line
    assert not (tmp_path / "o" / "results.csv").exists()
