"""Silent wrong answers (issue 21), each reproduced: tolerances that cannot
give an answer, indices that mean nothing, a maximum at the horizon taken
for a peak, no pulse taken for one, physically inconsistent settings."""
import subprocess
import sys

import numpy as np
import pytest

import pdbfs
from pdbfs.errors import ParameterError
from pdbfs.models import paper_rig


def cli(*args, cwd=None, timeout=300):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=timeout, cwd=cwd)


def one_line_error(r, *fragments):
    assert r.returncode == 2, (r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error:"), r.stderr
    for f in fragments:
        assert f in lines[0], lines[0]


# -- tolerances: one rule for every path ---------------------------------------------

@pytest.mark.parametrize("rtol", [1.0, 10.0, 0.2, 1e-16])
def test_tolerances_without_a_meaningful_answer_are_refused_everywhere(rtol, tmp_path):
    rig = paper_rig()
    with pytest.raises(ParameterError, match="rtol"):
        rig.simulate(0.02, rtol=rtol)
    with pytest.raises(ParameterError, match="rtol"):
        rig.simulate(0.02, rtol=rtol, backend="c")
    with pytest.raises(ParameterError, match="rtol"):
        pdbfs.sweep(rig, {"hammer.v0": [2.0, 3.0]}, rtol=rtol)
    with pytest.raises(ParameterError, match="rtol"):
        pdbfs.trajectory_function(rig, ["oil.pressure"], inputs=["oil.k"], rtol=rtol)


def test_the_cli_refuses_rtol_1_in_one_line(tmp_path):
    one_line_error(cli("simulate", "--rtol", "1", "--json", cwd=tmp_path), "rtol", "0.1")


def test_the_fmu_declares_the_same_rule():
    from pdbfs.fmu.variables import RTOL_MAX, RTOL_MIN
    from pdbfs.simulation.settings import RTOL_MAX as S_MAX, RTOL_MIN as S_MIN
    assert (RTOL_MIN, RTOL_MAX) == (S_MIN, S_MAX)
    paper_rig().simulate(0.002, rtol=RTOL_MAX)     # the edges themselves are allowed
