"""What a newcomer trips over first: files written into the repository by
the tests, numpy reprs in messages, a sensitivity warning about -0.000, a
plot titled only "pdbfs", a description that forgets FMI 3.0, a set-up that
is silent for minutes."""
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from pdbfs.errors import ParameterError, plain

ROOT = Path(__file__).resolve().parents[1]


def test_tests_run_outside_the_repository():
    """conftest.py puts every test in a temporary folder: a command writing to
    its default out/ (as one hydraulic-rig test did) writes there."""
    assert ROOT not in Path.cwd().resolve().parents and Path.cwd().resolve() != ROOT


def test_the_browser_test_leaves_the_tracked_screenshot_alone():
    src = (ROOT / "tests" / "test_app.py").read_text()
    assert '"figures" / "app.png"' not in src and "PDBFS_APP_SCREENSHOT" in src


def test_numbers_in_messages_are_plain():
    assert plain(np.float64(3.0)) == "3" and plain(np.int64(7)) == "7"
    assert plain({"hammer.v0": np.float64(1.5), "n": [np.float32(2.5)]}) == \
        "{'hammer.v0': 1.5, 'n': [2.5]}"
    from pdbfs.models import paper_rig
    with pytest.raises(ParameterError) as err:
        paper_rig().simulate(0.001, n_out=11, params={"hammer.v0": np.array([1.0, 2.0])})
    assert "np." not in str(err.value)
    from pdbfs.cli import plain_text
    assert plain_text("x = np.float64(0.25), n = np.int64(3)") == "x = 0.25, n = 3"


def test_an_index_within_its_interval_of_zero_is_no_problem():
    from pdbfs.studies.sensitivity import Sensitivity
    arr = lambda *v: np.array(v, float)   # noqa: E731
    s = Sensitivity(["a", "b"], ["peak_pressure"], {"peak_pressure": arr(-4e-5, 0.98)},
                    {"peak_pressure": arr(0.002, 0.01)}, {"peak_pressure": arr(0.001, 0.99)},
                    {"peak_pressure": arr(0.001, 0.01)}, 4096, 16384, {})
    assert s.problems() == []
    s.S1["peak_pressure"][0] = -0.05                          # below 0 beyond its interval
    (problem,) = s.problems()
    assert "-0.05" in problem and "-0.000" not in problem


def test_the_plot_names_the_rig_the_horizon_and_the_changed_settings(tmp_path):
    from pdbfs.models import paper_rig
    fig = paper_rig().simulate(0.003, n_out=31, params={"hammer.v0": 4.23}).plot()
    title = fig._suptitle.get_text()
    assert "rig pdbfs" in title and "0.003 s" in title and "hammer.v0 = 4.23 m/s" in title
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--rig", "paper",
                        "--t-end", "0.003", "--out", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_pyproject_names_both_fmi_versions():
    text = (ROOT / "pyproject.toml").read_text()
    desc = re.search(r'^description = "(.*)"', text, flags=re.M).group(1)
    assert "FMI 2.0 and 3.0" in desc


def test_setup_says_what_it_does_before_each_long_step():
    script = (ROOT / "scripts" / "setup.sh").read_text()
    steps = re.findall(r'^\s*step "([^"]+)"', script, flags=re.M)
    assert len(steps) >= 5
    lines = script.splitlines()
    pip = next(i for i, ln in enumerate(lines) if "pip install --quiet" in ln)
    assert lines[pip - 1].lstrip().startswith('step "')       # the longest step is announced
    assert "SUNDIALS" in " ".join(steps) and steps[-1] == "done"
