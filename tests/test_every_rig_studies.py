"""Every rig goes through the studies that take many points: sweep,
sensitivity and design map, at the smallest sizes. A summary value of a new
shape (the drop rig's list of blow durations) once ended each of them in a
TypeError."""
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest

from pdbfs.errors import PdbfsError
from pdbfs.models import RIGS
from pdbfs.studies import design_map, sensitivity, sweep
from pdbfs.studies.sweeps.runner import LIST_KEYS


def two_settings(rig):
    """The first two parameters with a positive default (masses, lengths, heights)."""
    dae = rig.compile()
    names = [p.name for p in dae.params if p.value > 0 and p.name not in dae.calculated]
    values = {p.name: p.value for p in dae.params}
    return [(n, values[n]) for n in names[:2]]


def horizon(rig):
    return getattr(rig, "default_t_end", 0.02)


@pytest.mark.parametrize("name", list(RIGS))
def test_every_rig_sweeps_and_every_list_has_a_column_form(name):
    rig = RIGS[name]()
    (a, va), _ = two_settings(rig)
    t_end = horizon(rig)
    res = sweep(rig, {a: [va, 1.01 * va]}, t_end=t_end, n_out=int(round(t_end / 1e-3)) + 1,
                workers=1, progress=False)
    assert not res.failed, [p.error for p in res.failed]
    direct = rig.simulate(t_end, n_out=int(round(t_end / 1e-3)) + 1, params={a: va}).summary()
    for key, value in direct.items():
        if isinstance(value, (list, tuple)):          # a list is stored whole, as JSON text
            assert key in LIST_KEYS
            stored = res.points[0].summary[key]
            assert [v is None for v in stored] == [v is None for v in value]
            assert [v for v in stored if v is not None] == pytest.approx(
                [v for v in value if v is not None], rel=1e-9)
        elif key != "complete" and value is not None:
            # a sweep point and a run may take different integrators (a solved start
            # is swept point by point): they agree to the default path's 1e-7
            assert res.values(key)[0] == pytest.approx(value, rel=1e-7), key


@pytest.mark.parametrize("name", list(RIGS))
def test_every_rig_gives_sensitivity_indices_and_a_design_map(name):
    rig = RIGS[name]()
    (a, va), (b, vb) = two_settings(rig)
    t_end = horizon(rig) if name == "drop" else 0.03
    # at rest, or a valve whose command (an input) is not given: no pulse anywhere,
    # so no indices, said so
    if name == "drop-rest" or rig.inputs():
        with pytest.raises(PdbfsError, match="no output is defined at every point.*no pulse"):
            sensitivity(rig, {a: (0.99 * va, 1.01 * va)}, n=1, t_end=t_end, workers=1,
                        backend="casadi", progress=False)
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")               # n = 1 is flagged as too small: it is
        s = sensitivity(rig, {a: (0.99 * va, 1.01 * va)}, n=1, t_end=t_end, workers=1,
                        backend="casadi", progress=False)
    assert s.points == 3 and set(s.S1) == {"peak_pressure", "time_of_peak", "pulse_duration"}
    m = design_map(rig, (a, 0.99 * va, 1.01 * va), (b, 0.99 * vb, 1.01 * vb), n=2, t_end=t_end)
    peak = m.values["peak_pressure"]
    assert peak.shape == (2, 2) and np.all(np.isfinite(peak)) and np.all(peak > 0)


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, timeout=300, cwd=cwd)


def test_the_drop_rig_through_the_command_line(tmp_path):
    r = cli("sweep", "--rig", "drop", "--set", "h=0.3,0.4", "--out", "D", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    points = json.loads(r.stdout)["points"]
    assert [len(p["summary"]["impact_durations"]) for p in points] == \
        [p["summary"]["impact_count"] for p in points]
    assert "Traceback" not in r.stderr
    r = cli("sweep", "--rig", "drop", "--sample", "lhs:2", "--range", "h=0.3:0.5", "--out", "E",
            cwd=tmp_path)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    r = cli("sensitivity", "--rig", "drop", "--range", "h=0.3:0.5", "--n", "1", "--t-end", "1.5",
            "--backend", "casadi", cwd=tmp_path)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    r = cli("design-map", "--rig", "drop", "--x", "h=0.3:0.5", "--y", "oil.k=2e8:3e8", "--n", "2",
            "--t-end", "1.5", "--out", "M", cwd=tmp_path)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
