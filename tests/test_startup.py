"""What a process imports before its first number (the figures are the
benchmark's: scripts/bench_startup.py): ``import pdbfs`` leaves out the
compiled backend's build, pip's index and the studies; a sweep in memory
leaves out scipy's optimizers and statistics, pandas and the progress bar's
module, and its points and values are those its pandas table gives when
asked for."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

import pdbfs
from pdbfs.models import paper_rig

#: modules a process that has only imported pdbfs has no use for yet
NOT_ON_IMPORT = ("numpy", "casadi", "pdbfs.modelling", "pdbfs.simulation", "urllib.request", "scipy",
                 "pandas", "matplotlib", "tqdm", "pdbfs.native.pipindex",
                 "pdbfs.native.sundials", "pdbfs.native.codegen", "pdbfs.simulation.run.compiled_build",
                 "pdbfs.studies")
#: ... and one whose command line has shown its help or refused an unknown option
NOT_BEFORE_OPTIONS = ("casadi", "pdbfs.modelling", "pdbfs.simulation", "pdbfs.rig", "scipy", "pandas")
#: ... and one that has run a sweep in memory and read its values and points
NOT_IN_A_SWEEP = ("scipy.optimize", "scipy.stats", "scipy.interpolate", "pandas", "tqdm",
                  "pdbfs.native.pipindex")


def _imported(code: str, names) -> list[str]:
    """Which of ``names`` a new process running ``code`` has imported."""
    probe = f"{code}\nimport json, sys\nprint(json.dumps([m for m in {list(names)!r} if m in sys.modules]))"
    r = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_import_pdbfs_leaves_out_the_build_the_index_and_the_studies():
    assert _imported("import pdbfs", NOT_ON_IMPORT) == []


def test_import_pdbfs_imports_its_names_on_first_use():
    code = ("import pdbfs\nassert 'casadi' not in __import__('sys').modules\n"
            "from pdbfs import Rig, simulate, sweep, time\nimport pdbfs.rig, pdbfs.simulation, pdbfs.studies\n"
            "assert Rig is pdbfs.rig.Rig and simulate is pdbfs.simulation.simulate\n"
            "assert sweep is pdbfs.studies.sweep and {'Rig', 'sweep'} <= set(dir(pdbfs))")
    assert _imported(code, ["casadi", "pdbfs.studies"]) == ["casadi", "pdbfs.studies"]


@pytest.mark.parametrize("argv", [["--help"], ["simulate", "--help"], ["sweep", "--bogus"]])
def test_the_command_line_reads_its_options_before_the_modelling_layers(argv):
    code = ("import contextlib, io, pdbfs.cli\nwith contextlib.redirect_stdout(io.StringIO()), "
            "contextlib.redirect_stderr(io.StringIO()):\n    try:\n"
            f"        pdbfs.cli.main({argv!r})\n    except SystemExit as e:\n"
            "        assert e.code in (0, 2), e.code")
    assert _imported(code, NOT_BEFORE_OPTIONS) == []


def test_a_sweep_in_memory_imports_no_fit_statistics_pandas_or_bar():
    code = ("import pdbfs\nfrom pdbfs.models import paper_rig\nrig = paper_rig()\n"
            "res = pdbfs.sweep(rig, {'hammer.v0': [2.0, 2.73]}, progress=False)\n"
            "assert len(res) == 2 and res.n_failed == 0 and res.values('peak_pressure')[1] > 0\n"
            "assert res.points[0].summary['peak_pressure'] > 0")
    assert _imported(code, NOT_IN_A_SWEEP) == []


@pytest.mark.parametrize("backend", ["c", "casadi"])
def test_a_sweeps_points_and_values_are_its_tables(backend):
    res = pdbfs.sweep(paper_rig(), {"hammer.v0": [2.73, 1e150, 4.23], "seal.c": [2.556e4, -1.0]},
                      backend=backend, progress=False)
    held = res.points                                   # from the columns held
    frame = res.frame                                   # pandas, made now
    made = res._make_points(frame)
    assert len(res) == len(frame) == 6 and res.n_failed == int((frame["error"] != "").sum()) >= 3
    for a, b in zip(held, made):
        assert (a.index, a.params, a.error, a.error_type) == (b.index, b.params, b.error, b.error_type)
        assert (a.summary is None) == (b.summary is None)
        for k in a.summary or {}:
            va, vb = a.summary[k], b.summary[k]
            assert va == vb or (isinstance(va, float) and math.isnan(va) and math.isnan(vb)), k
    for key in ("hammer.v0", "peak_pressure", "pulse_duration", "complete"):
        assert np.array_equal(res.values(key), frame[key].to_numpy(dtype=float, na_value=np.nan),
                              equal_nan=True), key
