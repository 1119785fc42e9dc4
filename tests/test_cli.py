"""The command line as a user types it."""
import csv
import json
import subprocess
import sys

import numpy as np
import pytest

from pdbfs.models import paper_rig

KEYS = ["peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
        "max_piston_displacement", "restitution_coefficient", "complete"]


def run(*args):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=300)


def test_simulate_json_writes_results_and_plot(tmp_path):
    r = run("simulate", "--set", "hammer.v0=4.23", "--t-end", "0.015", "--out", str(tmp_path),
            "--json")
    assert r.returncode == 0, r.stderr
    summary = json.loads(r.stdout)
    assert list(summary) == KEYS + ["stats"]
    assert summary["complete"] is True and summary["stats"]["steps"] > 100
    direct = paper_rig().simulate(0.015, params={"hammer.v0": 4.23}).summary()
    for k in KEYS:
        assert summary[k] == pytest.approx(direct[k], rel=1e-9)
    with open(tmp_path / "results.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][0] == "time [s]" and "oil.pressure [Pa]" in rows[0]
    data = np.array(rows[1:], dtype=float)
    assert data.shape[0] == 2001 and data[-1, 0] == pytest.approx(0.015)
    col = rows[0].index("oil.pressure [Pa]")
    assert data[:, col].max() == pytest.approx(summary["peak_pressure"], rel=1e-4)
    png = (tmp_path / "results.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000


def test_simulate_prints_a_table(tmp_path):
    r = run("simulate", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    for k in KEYS:
        assert k in r.stdout
    assert "Pa" in r.stdout


def test_params_lists_every_parameter_with_unit_and_description():
    r = run("params")
    assert r.returncode == 0, r.stderr
    dae = paper_rig().compile()
    for p in dae.params:
        line = next(l for l in r.stdout.splitlines() if l.split()[0] == p.name)
        assert p.unit in line and p.description[:20] in line
    for name in ("hammer.m", "contact.k", "contact.D", "oil.k", "oil.n", "seal.c", "mount.k"):
        assert name in r.stdout


def test_error_is_one_line_without_traceback(tmp_path):
    r = run("simulate", "--set", "oil.k=nan", "--out", str(tmp_path))
    assert r.returncode == 2
    assert r.stderr.strip() == "pdbfs: error: oil.k = nan: must be finite (Oil column " \
        "stiffness (unit N/m^n); the paper's k2, N/m)"


def test_undefined_summary_values_are_null_not_nan(tmp_path):
    # 3 ms: the hammer has not stopped yet, so no restitution can be computed
    r = run("simulate", "--t-end", "0.003", "--out", str(tmp_path), "--json")
    assert r.returncode == 0, r.stderr
    assert "NaN" not in r.stdout
    summary = json.loads(r.stdout)
    assert summary["restitution_coefficient"] is None and summary["pulse_duration"] is None
    # the pressure rises higher after 3 ms: the highest so far is no peak
    assert summary["complete"] is False and summary["peak_pressure"] is None
    warning = [l for l in r.stderr.splitlines() if l.startswith("pdbfs: warning:")]
    assert len(warning) == 1 and "still running at t_end = 0.003 s" in warning[0]
    assert "is not its peak" in warning[0]
