"""The page's layer over the API (pdbfs.app.workbench), without a browser:
controls for every parameter, the command line's messages, uploads read as
`pdbfs calibrate` reads files, studies that start from the page's settings."""
from __future__ import annotations

import base64
import math
import subprocess
import sys

import numpy as np

import pytest

pytest.importorskip("dash")

from pdbfs.app.workbench import LOG_UNITS, Workbench, drop_height, workbench  # noqa: E402
from pdbfs.components.laws import impact_velocity  # noqa: E402
from pdbfs.errors import DataError, ParameterError  # noqa: E402
from pdbfs.models import paper_rig  # noqa: E402


@pytest.fixture(scope="module")
def wb():
    return workbench("paper")


def test_every_parameter_is_a_control_with_unit_and_description(wb):
    params = paper_rig().compile().params
    by_name = {c.name: c for c in wb.controls}
    for p in params:
        c = by_name[p.name]
        assert (c.unit, c.description, c.default) == (p.unit, p.description, p.value)
        assert c.lo <= p.value <= c.hi
        assert c.log == (p.unit.startswith(LOG_UNITS) and p.value > 0)
        s = c.to_slider(p.value)
        assert c.from_slider(s) == pytest.approx(p.value, rel=1e-12)
    for name in ("contact.k", "contact.D", "oil.k", "seal.c", "mount.k"):
        assert by_name[name].log, name
    h = by_name["hammer.h"]
    assert h.derived == "hammer.v0"
    assert impact_velocity(h.default) == pytest.approx(2.73, rel=1e-12)
    names = [c.name for c in wb.controls]
    assert names.index("hammer.h") == names.index("hammer.v0") + 1


def test_a_rig_with_its_own_drop_height_gets_no_second_one():
    drop = Workbench("drop")
    assert drop.height is None and "h" in [c.name for c in drop.controls]


def test_field_errors_are_the_command_line_s(wb, tmp_path):
    for name, text in (("hammer.m", "-1"), ("oil.k", "0"), ("seal.c", "-5")):
        with pytest.raises(ParameterError) as err:
            wb.check(name, text)
        cli = subprocess.run([sys.executable, "-m", "pdbfs.cli", "simulate", "--set", f"{name}={text}",
                              "--out", str(tmp_path / "o")], capture_output=True, text=True)
        assert cli.returncode == 2
        assert cli.stderr.strip() == f"pdbfs: error: {err.value}"
    with pytest.raises(ParameterError, match=r"^hammer.m: 'heavy' is not a number$"):
        wb.check("hammer.m", "heavy")
    with pytest.raises(ParameterError, match=r"^hammer.h = -0.2 m: must be >= 0"):
        wb.check("hammer.h", "-0.2")
    assert wb.check("hammer.h", "0.5") == {"hammer.h": 0.5, "hammer.v0": impact_velocity(0.5)}
    assert wb.check("hammer.v0", "4") == {"hammer.v0": 4.0, "hammer.h": drop_height(4.0)}


def test_an_upload_is_read_as_a_trace_file_and_named_as_uploaded(wb):
    res = paper_rig().simulate(0.02, backend="c")
    csv = "time [s],oil.pressure [Pa]\n" + "".join(
        f"{t!r},{p!r}\n" for t, p in zip(res.t[::20].tolist(), res["oil.pressure"][::20].tolist()))
    url = "data:text/csv;base64," + base64.b64encode(csv.encode()).decode()
    tr = wb.read_upload("shot 12.csv", url)
    assert len(tr.t) == 101 and tr.y.max() == res["oil.pressure"][::20].max()
    bad = "data:text/csv;base64," + base64.b64encode(b"time,p\n0,1\n1,x\n").decode()
    with pytest.raises(DataError) as err:
        wb.read_upload("bad.csv", bad)
    assert str(err.value).startswith("trace file 'bad.csv': ") and "/tmp" not in str(err.value)


def test_studies_start_from_the_page_s_settings(wb):
    """Calibrating oil.k to a trace made with another drop height only works
    if the page's drop height (not the rig's default) is held fixed."""
    settings = {**wb.defaults(), **wb.check("hammer.h", "0.6")}
    res = paper_rig().simulate(0.02, params={"hammer.v0": settings["hammer.v0"], "oil.k": 3e8},
                               backend="c")
    trace = (res.t[::10], res["oil.pressure"][::10])
    cal = wb.calibrate(settings, trace, ["oil.k"])
    assert cal["params"]["oil.k"] == pytest.approx(3e8, rel=1e-4)
    des = wb.design(settings, trace, ["oil.k"])
    assert des["params"]["oil.k"] == pytest.approx(3e8, rel=1e-4)
    both = wb.calibrate(wb.defaults(), trace, ["hammer.h", "oil.k"])
    assert both["params"]["hammer.h"] == pytest.approx(0.6, rel=1e-4)
    assert math.isfinite(both["std"]["hammer.h"])


def test_long_actions_report_their_progress():
    """What the page shows while it works comes from the API itself."""
    import pdbfs
    from pdbfs.models import paper_rig
    seen = []
    pdbfs.design_map(paper_rig(), "hammer.v0=2:4", "oil.k=2e8:3e8", n=3, backend="c",
                     progress=lambda done, total: seen.append((done, total)))
    assert seen and seen[-1] == (9, 9) and all(t == 9 for _, t in seen)
    runs = []
    res = paper_rig().simulate(t_out=np.linspace(0, 0.016, 161), params={"oil.k": 3e8})
    cal = pdbfs.calibrate(paper_rig(), (res.t, res["oil.pressure"]), ["oil.k"], starts=1,
                          progress=runs.append)
    assert runs == list(range(1, cal.evaluations + 1))
