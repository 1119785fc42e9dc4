"""Sweeps past one machine and past memory: samples, chunks on disk, resuming
an interrupted sweep, a Dask LocalCluster losing a worker, global
sensitivity; bad input named in one line."""
import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest
from scipy.stats import qmc

import pdbfs
from pdbfs.cli import main
from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig
from pdbfs.studies import Grid, Sample, SweepResult
from pdbfs.studies.sweeps import runner as sweep_runner

RANGES = {"hammer.v0": (1.5, 5.5), "oil.k": (1e8, 1e9), "seal.c": (2.5e3, 2.5e6, "log")}


def test_samples_fill_their_ranges_reproducibly():
    lhs = Sample("lhs", 64, RANGES, seed=1)
    X = lhs.all()
    assert X.shape == (64, 3) and np.array_equal(X, Sample("lhs", 64, RANGES, seed=1).all())
    # a Latin hypercube: one point in each of the 64 strata of every parameter
    u = (X[:, 0] - 1.5) / 4.0
    assert sorted(np.floor(u * 64).astype(int)) == list(range(64))
    w = np.log(X[:, 2] / 2.5e3) / np.log(1e3)                    # log range: uniform in log
    assert sorted(np.floor(w * 64).astype(int)) == list(range(64))
    sob = Sample("sobol", 256, {"oil.k": (1e8, 1e9)}, seed=2).all()
    assert qmc.discrepancy((sob - 1e8) / 9e8) < qmc.discrepancy(np.random.default_rng(2).random((256, 1)))
    mc = Sample("mc", 20000, dists={"oil.k": ("normal", 2.228e8, 1e7)}, seed=3).all()[:, 0]
    assert abs(mc.mean() - 2.228e8) < 4 * 1e7 / np.sqrt(20000) and abs(mc.std() / 1e7 - 1) < 0.03
    assert np.array_equal(lhs.block(10, 20), X[10:20])          # blocks are slices of the set


def test_a_monte_carlo_tolerance_study():
    """How much the peak pressure scatters when the oil stiffness and the seal
    vary as in service: the scatter follows the oil stiffness."""
    pts = Sample("mc", 400, dists={"oil.k": ("normal", 2.228e8, 1.0e7),
                                   "seal.c": ("lognormal", 2.556e4, 0.2)}, seed=5)
    res = pdbfs.sweep(paper_rig(), pts, backend="c")
    peak, k = res.values("peak_pressure"), res.values("oil.k")
    assert res.n_failed == 0 and 0.005 < peak.std() / peak.mean() < 0.1
    assert np.corrcoef(k, peak)[0, 1] > 0.5


def test_chunks_on_disk_resume_and_refuse_another_sweep(tmp_path):
    out = tmp_path / "sw"
    pts = Sample("lhs", 120, RANGES, seed=4)
    first = pdbfs.sweep(paper_rig(), pts, backend="c", out=out, chunk_size=25)
    files = sorted((out / "chunks").glob("chunk-*.parquet"))
    assert len(files) == 5 and (out / "manifest.json").is_file() and first.computed == 120
    stamps = [f.stat().st_mtime_ns for f in files]
    again = pdbfs.sweep(paper_rig(), pts, backend="c", out=out, chunk_size=25)
    assert again.computed == 0 and [f.stat().st_mtime_ns for f in files] == stamps
    assert again.frame.equals(first.frame) and len(again) == 120
    with pytest.raises(ParameterError, match="holds another sweep"):
        pdbfs.sweep(paper_rig(), Sample("lhs", 120, RANGES, seed=5), backend="c", out=out,
                    chunk_size=25)
    csv = pdbfs.sweep(paper_rig(), pts, backend="c", out=tmp_path / "csv", format="csv",
                      chunk_size=50)
    assert np.allclose(csv.values("peak_pressure"), first.values("peak_pressure"), rtol=1e-15)


def test_a_killed_sweep_resumes_without_recomputing(tmp_path):
    out = tmp_path / "killed"
    # 0.2 s per point, so that the sweep lasts long enough to be killed part way
    # (at 20 ms its 12 chunks could all be written between two looks)
    cmd = [sys.executable, "-m", "pdbfs.cli", "sweep", "--set", "hammer.v0=1.5:5.5:60",
           "--set", "seal.c=2e4,3e4", "--t-end", "0.2", "--no-plot", "--chunk", "10",
           "--workers", "1", "--out", str(out), "--quiet"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 120
    while len(list((out / "chunks").glob("chunk-*.parquet"))) < 3 and time.time() < deadline:
        time.sleep(0.05)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    done = {f.name: f.stat().st_mtime_ns for f in (out / "chunks").glob("chunk-*.parquet")}
    assert 3 <= len(done) < 12, "the sweep was not interrupted part way"
    r = subprocess.run(cmd[:-1] + ["--json"], capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["n_points"] == 120 and doc["computed"] == 120 - 10 * len(done)
    assert {f: (out / "chunks" / f).stat().st_mtime_ns for f in done} == done   # not recomputed
    frame = SweepResult.load(out).frame
    assert list(frame["point"]) == list(range(120))                         # none lost or twice
    assert frame["error"].eq("").all() and frame["peak_pressure"].notna().all()
    assert not list((out / "chunks").glob(".*part"))                    # no half-written file


def test_dask_cluster_losing_a_worker_gives_the_local_answer(tmp_path):
    from distributed import Client, LocalCluster
    pts = Sample("lhs", 240, {"hammer.v0": (1.5, 5.5), "oil.k": (1e8, 1e9)}, seed=3)
    local = pdbfs.sweep(paper_rig(), pts, workers=1, chunk_size=8)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=50) as cluster, Client(cluster) as client:
        out = tmp_path / "dask"

        def kill_one_worker():
            while len(list((out / "chunks").glob("chunk-*"))) < 4:
                time.sleep(0.02)
            pid = next(iter(client.run(os.getpid).values()))
            os.kill(pid, signal.SIGKILL)
        killer = threading.Thread(target=kill_one_worker, daemon=True)
        killer.start()
        res = pdbfs.sweep(paper_rig(), pts, client=client, out=out, chunk_size=8)
        killer.join(timeout=5)
        assert not killer.is_alive()
        # point for point the local answer: nothing lost, nothing twice
        assert res.frame.drop(columns="error").equals(local.frame.drop(columns="error"))
        # the rig was built once per worker process, not once per task
        assert all(n <= 1 for n in client.run(lambda: len(sweep_runner._RUNNERS)).values())


def test_sensitivity_quantifies_the_paper(tmp_path, capsys):
    s = pdbfs.sensitivity(paper_rig(), RANGES, n=128, t_end=0.2)   # the stiffest seal: 120 ms
    ST = {o: dict(zip(s.names, s.ST[o])) for o in s.outputs}
    assert s.points == 128 * 5
    assert ST["peak_pressure"]["hammer.v0"] > 0.3                 # magnitude: impact velocity
    assert ST["pulse_duration"]["hammer.v0"] < 0.05               # not the duration
    assert ST["pulse_duration"]["seal.c"] > 0.3 and ST["pulse_duration"]["oil.k"] > 0.3
    assert main(["sensitivity", "--range", "hammer.v0=1.5:5.5", "--range", "oil.k=1e8:1e9",
                 "--n", "32", "--json", "--quiet", "--out", str(tmp_path)]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert set(doc["indices"]) == {"peak_pressure", "time_of_peak", "pulse_duration"}
    assert (tmp_path / "sensitivity.png").stat().st_size > 10000


SWEEP_RSS = """
import sys
import numpy as np
import pdbfs
from pdbfs.models import paper_rig
from pdbfs.studies import Grid
n, out = int(sys.argv[1]), sys.argv[2]
pdbfs.sweep(paper_rig(), Grid({"hammer.v0": np.linspace(2, 4, n)}), t_end=0.002, n_out=21,
            backend="c", out=out, chunk_size=100, progress=False)
# KiB: VmHWM, this process's own since its exec (ru_maxrss also holds the test
# process's at the fork)
with open("/proc/self/status") as st:
    print(next(ln.split()[1] for ln in st if ln.startswith("VmHWM:")))
"""


def test_memory_stays_bounded_when_chunks_go_to_disk(tmp_path):
    """Peak RSS of a whole process (pyarrow and C memory included), not tracemalloc."""
    def peak_kib(n):
        run = subprocess.run([sys.executable, "-c", SWEEP_RSS, str(n), str(tmp_path / f"m{n}")],
                             capture_output=True, text=True, check=True)
        return int(run.stdout.split()[-1])
    peak_kib(100)                                       # build the library first
    small, large = peak_kib(1000), peak_kib(16000)
    assert large < small + 40 * 1024, (small, large)     # 16x the points, not 16x the memory


def fails(capsys, argv, *fragments):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("pdbfs: error:"), err
    for f in fragments:
        assert f in err, (f, err)


@pytest.mark.parametrize("args, fragments", [
    (["--sample", "lhs:10", "--range", "oil.k=5e8:1e8"], ("range of oil.k", "below")),
    (["--sample", "lhs:0", "--range", "oil.k=1e8:5e8"], ("N = 0",)),
    (["--sample", "lhs:-3", "--range", "oil.k=1e8:5e8"], ("N = -3",)),
    (["--sample", "mc:10", "--dist", "oil.k=weibull:1:2"], ("unknown distribution 'weibull'",)),
    (["--sample", "mc:10", "--dist", "oil.k=normal:2e8:-1"], ("spread must be > 0",)),
    (["--sample", "halton:10", "--range", "oil.k=1e8:5e8"], ("unknown sampler 'halton'",)),
    (["--sample", "lhs:10", "--range", "oil.kk=1e8:5e8"], ("oil.kk",)),
    (["--range", "oil.k=1e8:5e8"], ("need --sample",)),
])
def test_bad_sweep_input(tmp_path, capsys, args, fragments):
    fails(capsys, ["sweep", "--backend", "c", "--out", str(tmp_path / "o")] + args, *fragments)


def test_unreachable_scheduler_is_an_error_within_seconds(capsys):
    t0 = time.time()
    fails(capsys, ["sweep", "--set", "hammer.v0=2,3", "--dask", "tcp://127.0.0.1:9"],
          "cannot reach a Dask scheduler", "127.0.0.1:9")
    assert time.time() - t0 < 30


def test_an_output_folder_of_another_sweep_is_refused(tmp_path, capsys):
    out = str(tmp_path / "o")
    assert main(["sweep", "--sample", "lhs:20", "--range", "oil.k=1e8:5e8", "--backend", "c",
                 "--out", out, "--quiet", "--no-plot"]) == 0
    capsys.readouterr()
    fails(capsys, ["sweep", "--sample", "lhs:30", "--range", "oil.k=1e8:5e8", "--backend", "c",
                   "--out", out, "--quiet"], "holds another sweep", "--overwrite")
    assert main(["sweep", "--sample", "lhs:30", "--range", "oil.k=1e8:5e8", "--backend", "c",
                 "--out", out, "--quiet", "--overwrite"]) == 0
