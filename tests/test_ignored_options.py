"""Options are honoured or refused, never dropped: each case here once ran
with the option silently without effect (or the last of two values winning),
and is now refused in one line, exit status 2, before any work and with
nothing written. Samples too big for memory are refused up front, or drawn
in blocks (the same points as drawn whole), and a sweep streamed to disk is
reported without reading it whole."""
import time
import tracemalloc
import warnings

import numpy as np
import pytest
from scipy.stats import qmc

from pdbfs.cli import main
from pdbfs.errors import ParameterError

ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
KISTLER = str(ROOT / "docs" / "data" / "kistler_synthetic.csv")


@pytest.fixture
def refused(capsys, tmp_path, monkeypatch):
    """Run the command line in tmp_path: exit 2, one line naming ``words``,
    quickly, and nothing written there."""
    monkeypatch.chdir(tmp_path)

    def check(args, *words, within=20.0):
        t0 = time.time()
        status = main(args)
        err = capsys.readouterr().err.strip().splitlines()
        assert status == 2, (status, err)
        assert len(err) == 1 and err[0].startswith("pdbfs: error: "), err
        for w in words:
            assert w in err[0], (w, err[0])
        assert time.time() - t0 < within, err[0]
        assert list(tmp_path.iterdir()) == [], list(tmp_path.iterdir())
        return err[0]
    return check


# -- the same name twice: the last won -------------------------------------------------
@pytest.mark.parametrize("args", [
    ["simulate", "--set", "hammer.v0=1", "--set", "hammer.v0=5", "--out", "o"],
    ["modes", "--set", "oil.k=2e8", "--set", "oil.k=3e8"],
    ["design-map", "--x", "hammer.v0=1:2", "--y", "seal.c=1e4:2e4", "--set", "oil.k=2e8",
     "--set", "oil.k=3e8", "--out", "o"],
    ["calibrate", "--trace", KISTLER, "--free", "oil.k", "--set", "seal.c=1", "--set",
     "seal.c=2"],
])
def test_a_setting_given_twice_is_refused(refused, args):
    name = args[args.index("--set") + 1].split("=")[0]
    refused(args, f"--set {name} given twice", "give it once")


@pytest.mark.parametrize("args, words", [
    (["sweep", "--sample", "lhs:4", "--range", "hammer.v0=1:2", "--range", "hammer.v0=3:4",
      "--out", "o"], ["--range hammer.v0 given twice (1:2 and 3:4)"]),
    (["sweep", "--sample", "mc:4", "--dist", "oil.k=normal:2e8:1e7", "--dist",
      "oil.k=normal:3e8:1e7", "--out", "o"], ["--dist oil.k given twice"]),
    (["sensitivity", "--range", "hammer.v0=1:2", "--range", "hammer.v0=1:3", "--n", "1",
      "--out", "o"], ["--range hammer.v0 given twice"]),
    (["calibrate", "--trace", KISTLER, "--free", "oil.k", "--bounds", "oil.k=1e8:1e9",
      "--bounds", "oil.k=2e8:3e8"], ["--bounds oil.k given twice"]),
    (["sensitivity", "--range", "hammer.v0=1:2", "--n", "1", "--outputs",
      "peak_pressure,peak_pressure", "--out", "o"], ["'peak_pressure' is named twice"]),
])
def test_ranges_distributions_bounds_and_outputs_given_twice_are_refused(refused, args, words):
    refused(args, *words)


# -- options without effect --------------------------------------------------------------
@pytest.mark.parametrize("args, words", [
    (["modes", "--shape", "-3"], ["--shape -3", ">= 0"]),
    (["modes", "--shape", "2", "--json"], ["--shape 2", "JSON output holds every entry"]),
    (["sweep", "--set", "hammer.v0=1,2", "--seed", "3", "--out", "o"],
     ["--seed 3", "a --set grid has no seed"]),
    (["sweep", "--sample", "lhs:2", "--range", "hammer.v0=1:2", "--zip", "--out", "o"],
     ["--zip", "a --sample has no lists"]),
    (["sweep", "--set", "hammer.v0=1,2", "--format", "csv", "--out", "o"],
     ["--format csv", "writes no chunk files", "--no-plot"]),
    (["sweep", "--set", "hammer.v0=1,2", "--dask", "local", "--workers", "2", "--out", "o"],
     ["--workers 2", "--dask"]),
    (["calibrate", "--trace", KISTLER, "--free", "oil.k", "--t-end", "1e-6"],
     ["--t-end 1e-06 s ends before the last sample", "kistler_synthetic.csv", "0.02149 s"]),
    (["design", "--target", KISTLER, "--free", "oil.k", "--t-end", "0.001"],
     ["--t-end 0.001 s ends before the last sample", "cut the target curve"]),
    (["calibrate", "--trace", KISTLER, "--free", "oil.k", "--starts", "1", "--seed", "5"],
     ["--seed 5", "--starts 2 or more"]),
    (["export-fmu", "-o", "x.zip"], ["x.zip", "ends in .fmu", "x.fmu"]),
    (["export-fmu", "-o", "model"], ["model", "ends in .fmu"]),
])
def test_an_option_without_effect_is_refused(refused, args, words):
    refused(args, *words)


def test_the_options_still_work_where_they_have_an_effect(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["modes", "--shape", "1"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines()[2:] if r.strip()]
    assert max(r.count(",") for r in rows) == 0          # one entry per shape
    assert main(["modes", "--shape", "0"]) == 0
    assert main(["sweep", "--sample", "lhs:2", "--range", "hammer.v0=2:3", "--seed", "7",
                 "--format", "csv", "--out", "s", "--quiet", "--workers", "1"]) == 0
    assert list((tmp_path / "s" / "chunks").glob("chunk-*.csv"))


def test_the_api_refuses_chunk_settings_without_chunks_and_workers_beside_a_cluster():
    from pdbfs.studies import sweep
    with pytest.raises(ParameterError, match="format= is about the chunk files in out="):
        sweep("paper", {"hammer.v0": [2.0]}, format="csv")
    with pytest.raises(ParameterError, match="overwrite= is about the chunk files"):
        sweep("paper", {"hammer.v0": [2.0]}, overwrite=True)
    with pytest.raises(ParameterError, match="workers = 2 is for this machine"):
        sweep("paper", {"hammer.v0": [2.0]}, workers=2, client=object())


def test_an_fmu_named_otherwise_is_refused_by_the_api_too(tmp_path):
    from pdbfs.errors import ExportError
    from pdbfs.fmu import export_fmu
    from pdbfs.models import paper_rig
    with pytest.raises(ExportError, match="ends in .fmu"):
        paper_rig().export_fmu(tmp_path / "x.zip")
    with pytest.raises(ExportError, match="ends in .fmu"):
        export_fmu(paper_rig().compile(), tmp_path / "x.zip")
    assert list(tmp_path.iterdir()) == []


def test_unknown_sensitivity_outputs_are_refused_before_any_run(monkeypatch):
    import sys
    S = sys.modules["pdbfs.studies.sensitivity"]           # the module, not its function

    def no_run(*a, **k):
        raise AssertionError("the sweep ran")
    monkeypatch.setattr(S, "sweep", no_run)
    with pytest.raises(ParameterError, match="no summary value 'nope'"):
        S.sensitivity("paper", {"hammer.v0": (1, 2)}, n=1, outputs=["peak_pressure", "nope"])


# -- memory --------------------------------------------------------------------------------
def test_a_latin_hypercube_that_cannot_fit_is_refused_up_front(refused):
    import psutil
    line = refused(["sweep", "--sample", "lhs:1000000000", "--range", "hammer.v0=1:5"],
                   "sample lhs:1000000000", "of memory", "are available", "sobol:N or mc:N")
    need = float(line.split("about ")[1].split()[0]) * {"GB": 1e9, "TB": 1e12}[
        line.split("about ")[1].split()[1]]
    assert need > 0.8 * psutil.virtual_memory().available


def test_the_api_refuses_it_too():
    import pdbfs
    from pdbfs.studies import Sample
    t0 = time.time()
    with pytest.raises(ParameterError, match="a Latin hypercube is drawn whole"):
        pdbfs.sweep("paper", Sample("lhs", 10 ** 9, ranges={"hammer.v0": (1.0, 5.0)}))
    with pytest.raises(ParameterError, match="at most 2\\*\\*30"):
        Sample("sobol", 2 ** 31, ranges={"hammer.v0": (1.0, 5.0)})
    assert time.time() - t0 < 10


RANGES = {"hammer.v0": (1.0, 5.0), "oil.k": (1e8, 1e9, "log")}


def whole_draw(kind, n, seed):
    """The unit-cube points as scipy and numpy draw them in one call."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if kind == "lhs":
            return qmc.LatinHypercube(d=2, seed=seed).random(n)
        if kind == "sobol":
            return qmc.Sobol(d=2, scramble=True, seed=seed).random(n)
        return np.random.default_rng(seed).random((n, 2))


@pytest.mark.parametrize("kind", ["lhs", "sobol", "mc"])
def test_blocks_are_the_points_drawn_whole_in_any_order(kind):
    """So a sweep resumed from its chunk files goes on with the same points."""
    from pdbfs.studies import Sample
    n = 1000
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = Sample(kind, n, RANGES, seed=3)
    u = whole_draw(kind, n, 3)
    want = np.column_stack([1.0 + 4.0 * u[:, 0], np.exp(np.log(1e8) + u[:, 1] * np.log(10.0))])
    starts = list(range(0, n, 77))
    for a in starts[::2] + starts[1::2] + [0]:           # forwards, then back
        assert np.array_equal(s.block(a, min(a + 77, n)), want[a:a + 77]), a


@pytest.mark.parametrize("kind, n", [("mc", 10 ** 9), ("sobol", 2 ** 30)])
def test_big_samples_are_drawn_in_blocks(kind, n):
    """A billion points: a block at the end costs its own rows only (the
    whole set once took 16 GB before the first point was run)."""
    from pdbfs.studies import Sample
    s = Sample(kind, n, RANGES, seed=1)
    tracemalloc.start()
    try:
        a = n - 10_000 if kind == "mc" else 0
        block = s.block(a, a + 10_000)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert block.shape == (10_000, 2) and np.all(np.isfinite(block))
    assert peak < 5e6, peak                               # 10,000 x 2 doubles and change


def test_a_sweep_on_disk_is_reported_without_reading_it_whole(tmp_path):
    """The failures are counted and the table's head read a chunk at a time
    (a billion points read back whole would need the memory the chunks spared)."""
    import pdbfs
    from pdbfs.studies.sweeps.result import SweepResult
    from pdbfs.studies.sweeps.store import saved_points
    out = tmp_path / "sw"
    values = {"oil.k": [2e8, 2.2e8, 2.4e8, -1.0, 3e8, 3.2e8, 3.5e8]}   # -1 N/m: a failed point
    res = pdbfs.sweep("paper", values, out=out, chunk_size=2, workers=1, progress=False)
    again = SweepResult.load(out)
    failed, head = again.n_failed, again.table(limit=3)
    assert again._frame is None                           # neither read the whole table
    whole = SweepResult.load(out)
    assert failed == int((whole.frame["error"] != "").sum()) == res.n_failed
    assert head.splitlines()[1:4] == whole.table(limit=None).splitlines()[1:4]
    assert "4 more points" in head
    assert saved_points(out) == 7


def test_a_sobol_sample_off_a_power_of_two_is_said_once_when_made():
    from pdbfs.studies import Sample
    with pytest.warns(UserWarning, match="sobol:300: .* power of 2, e.g. 256 or 512"):
        s = Sample("sobol", 300, RANGES)
    with warnings.catch_warnings():
        warnings.simplefilter("error")                    # not again for each block
        s.block(0, 100), s.block(100, 300)
        Sample("sobol", 256, RANGES).block(0, 256)
