"""Each extra does its work (scripts/test_floor.sh runs this at the lowest
versions pyproject.toml allows): [parquet] sweep files, [dask] a sweep on a
LocalCluster, [sensitivity] Sobol' indices, [app] the workbench's Dash app."""
import math

import pytest

import pdbfs
from pdbfs.models import paper_rig


def test_parquet_sweep_files_read_back(tmp_path):
    pytest.importorskip("pyarrow")
    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.0, 3.0, 4.0]}, out=tmp_path / "s",
                      format="parquet", progress=False, t_end=0.012)
    files = list((tmp_path / "s" / "chunks").glob("chunk-*.parquet"))
    assert files
    back = pdbfs.studies.sweeps.SweepResult.load(tmp_path / "s")
    assert len(back) == 3 and back.n_failed == 0
    assert list(back.values("peak_pressure")) == pytest.approx(list(res.values("peak_pressure")),
                                                               rel=1e-12)


def test_a_sweep_on_a_local_dask_cluster_matches_one_here():
    pytest.importorskip("distributed")
    from pdbfs.studies.sweeps.cluster import close, connect
    values = {"hammer.v0": [2.0, 3.0]}
    here = pdbfs.sweep(paper_rig(), values, progress=False, t_end=0.012)
    client = connect("local", workers=1)
    try:
        there = pdbfs.sweep(paper_rig(), values, client=client, progress=False, t_end=0.012)
    finally:
        close(client)
    assert list(there.values("peak_pressure")) == pytest.approx(
        list(here.values("peak_pressure")), rel=1e-12)


def test_sobol_indices_of_a_single_parameter():
    """One parameter explains all of the variance: its first-order and total
    indices are 1, within SALib's own 95 % interval."""
    pytest.importorskip("SALib")
    s = pdbfs.sensitivity(paper_rig(), {"hammer.v0": (2.0, 4.0)}, n=64, progress=False,
                          t_end=0.02, outputs=["peak_pressure"])
    got = s.to_dict()["indices"]["peak_pressure"]["hammer.v0"]
    for key in ("S1", "ST"):
        assert math.isfinite(got[key]) and abs(got[key] - 1.0) <= got[f"{key}_conf"], got


def test_the_workbench_app_is_built():
    pytest.importorskip("dash")
    from pdbfs.app import create_app
    app = create_app("paper")
    assert app.layout is not None and app.title.startswith("pdbfs workbench")
