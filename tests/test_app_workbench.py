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
    with pytest.raises(ParameterError, match=r"^hammer.h = -0.2 m: must be a finite number >= 0"):
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


# -- issue 21: every value a field takes simulates or is refused -----------------------

@pytest.mark.parametrize("name,text", [("hammer.v0", "1e300"), ("piston.v0", "1e308"),
                                       ("hammer.m", "1e308"), ("hammer.v0", "-1e308"),
                                       ("oil.k", "1e300"), ("seal.c", "5e-324"),
                                       ("hammer.h", "1e308"), ("hammer.h", "1e400"),
                                       ("contact.n", "1e308"), ("hammer.v0", "1e154"),
                                       ("oil.k", "1e-320")])
def test_a_huge_value_simulates_or_is_refused_in_one_line(wb, name, text):
    """No OverflowError: a value is refused with a ParameterError naming the
    parameter, or its settings draw a slider and simulate (or fail to, with
    the solver's own PdbfsError, which the page shows)."""
    from pdbfs.errors import PdbfsError
    try:
        changed = wb.check(name, text)
    except ParameterError as err:
        assert str(err).startswith(f"{name} = ") and "\n" not in str(err)
        return
    for k, v in changed.items():
        lo, hi = wb.control(k).slider_range(v)
        assert math.isfinite(lo) and math.isfinite(hi) and lo < hi
    try:
        res = wb.run({**wb.defaults(), **changed})
    except PdbfsError as err:
        assert "\n" not in str(err)
    else:
        assert np.all(np.isfinite(res["oil.pressure"]))


def test_an_impact_speed_whose_drop_height_overflows_is_refused(wb):
    with pytest.raises(ParameterError, match=r"^hammer.v0 = 1e300 m/s: too large .*hammer.h"):
        wb.check("hammer.v0", "1e300")


def test_failed_runs_are_worded_for_the_page():
    from pdbfs.app.interact import page_hint
    msg = page_hint("rig pdbfs: the solver failed ...; try method='bdf' or a max_step (CVODE ...)")
    assert "method='bdf'" not in msg and "max_step" not in msg and "method bdf" in msg
    assert page_hint("...; use t_end >= 0.016 s (duration ...)") == \
        "...; set t_end to 16 ms or more (duration ...)"


def test_a_failed_run_clears_the_plot_and_the_summary():
    """The page must not show the last good run under new settings."""
    from pdbfs.app.interact import draw
    settings = {"rig": "paper", "values": {**workbench("paper").defaults(), "oil.k": 1e30},
                "t_end": 0.02, "method": "bdf"}
    fig, summary, status = draw(settings, [], None, None, None)
    assert fig["data"] == [] and "failed" in fig["layout"]["annotations"][0]["text"]
    assert "sum-peak_pressure" not in str(summary) and "run-failed" in str(summary)
    assert "solver failed" in str(status)


def test_t_end_and_method_reach_the_run_and_the_hint_reaches_the_page(wb):
    """A run cut off names on the page the t_end that would hold the pulse;
    run at that length the pulse is complete, as simulate says."""
    short = wb.outcome(wb.defaults(), t_end=0.005)
    assert dict((k, v) for k, v, _ in short["rows"])["complete"] is False
    assert len(short["notes"]) == 1 and "use t_end >= " in short["notes"][0]
    need = float(short["notes"][0].split("use t_end >= ")[1].split(" s")[0])
    full = wb.outcome(wb.defaults(), t_end=need, method="bdf")
    rows = dict((k, v) for k, v, _ in full["rows"])
    assert rows["complete"] is True and not full["notes"]
    api = paper_rig().simulate(need, n_out=full["n"], backend=wb.backend, method="bdf").summary()
    assert rows["pulse_duration"] == api["pulse_duration"]
    assert wb.check_run("16", "adams") == (0.016, "adams")
    for t_end, method, match in (("0", "auto", "positive"), ("abc", "auto", "not a number"),
                                 ("1e9", "auto", "at most"), ("20", "rk4", "choose one of")):
        with pytest.raises(ParameterError, match=match):
            wb.check_run(t_end, method)


def test_each_rig_declares_its_page_defaults():
    """Calibration's free parameter and the design map's axes are the rig's
    own (a hydraulic rig gets no mount.s_rel0, nor the paper's oil.k range)."""
    from pdbfs.models import RIGS
    for name in ("paper", "drop", "paper-hydraulic", "hydraulic-pulse"):
        assert getattr(RIGS[name](), "page_defaults", None), name
        wb_ = workbench(name)
        d = wb_.study_defaults()
        names = [c.name for c in wb_.controls]
        for key in ("cal-free", "des-free"):
            assert d[key] and all(n in names for n in d[key]), (name, key)
        assert d["map-x"] in names and d["map-y"] in names and d["map-x"] != d["map-y"]
        assert d["map-x-lo"] < d["map-x-hi"] and d["map-y-lo"] < d["map-y-hi"]
        assert "mount.s_rel0" not in d["cal-free"]
    assert workbench("hydraulic-pulse").study_defaults()["cal-free"] == ["chamber.K"]
    assert workbench("drop").study_defaults()["map-x"] == "h"
    k = workbench("paper-hydraulic").study_defaults()
    assert k["map-y"] == "oil.K" and k["map-y-lo"] >= 1e9      # oil.K is about 2e9 Pa here


def test_forged_upload_names_and_sizes_get_one_line(wb, tmp_path, monkeypatch):
    from pdbfs.app import traces
    monkeypatch.setenv(traces.ENV, str(tmp_path / "traces"))
    from pdbfs.app.interact import upload
    rows = "".join(f"{k * 1e-3},{1 + (k == 5)}\n" for k in range(12))
    ok = "data:text/csv;base64," + base64.b64encode(("t,p\n" + rows).encode()).decode()
    settings = {"rig": "paper"}
    for name, why in (("..", "not a plain file name"), ("a" * 300 + ".csv", "at most 255"),
                      ("x\x00.csv", "NUL byte"), ("", "empty"), ("../etc/passwd", "not a plain"),
                      ("/tmp/x.csv", "not a plain")):
        kept, msg, _, _ = upload({"name": name, "contents": ok}, settings)
        assert why in msg and msg.startswith("trace file ") and "\n" not in msg and \
            "\x00" not in msg, (name, msg)
    big = "data:text/csv;base64," + "A" * int(traces.MAX_UPLOAD * 4 / 3 + 8)
    with pytest.raises(DataError, match=r"^trace file 'big.csv': 20.0 MB, more than the page"):
        wb.read_upload("big.csv", big)
    kept, msg, info, _ = upload({"name": "good.csv", "contents": ok}, settings)
    assert msg is None and "12 samples" in info and set(kept) == {"key", "name", "n", "t0", "t1"}
    t, y = traces.load(kept)
    assert list(y) == [1.0] * 5 + [2.0] + [1.0] * 6
    assert [p.name for p in (tmp_path / "traces").iterdir()] == [kept["key"] + ".npy"]
    for forged in ({"key": "../../etc/passwd"}, {"key": "0" * 32}, None):
        with pytest.raises(DataError):
            traces.load(forged)


def test_a_long_trace_is_drawn_decimated_with_its_peaks():
    from pdbfs.app.traces import MAX_DRAWN, decimate
    t = np.linspace(0, 1, 1_000_001)
    y = np.sin(40 * t) + (t == t[777_777]) * 5.0
    td, yd = decimate(t, y)
    assert len(td) <= MAX_DRAWN + 1 and yd.max() == y.max() and yd.min() == y.min()
    assert td[0] == 0 and td[-1] == 1 and np.all(np.diff(td) > 0)


def test_a_run_is_kept_for_pins_and_undo(wb):
    """Pins and going back to earlier settings do not simulate again."""
    import time
    s = {**wb.defaults(), "oil.k": 3.1e8}
    first = wb.outcome(s, t_end=0.02)
    t0 = time.perf_counter()
    again = wb.outcome(dict(s), t_end=0.02)
    assert again is first and time.perf_counter() - t0 < 0.01
    assert wb.outcome(s, t_end=0.019) is not first


def test_repeated_parts_are_drawn_only_when_asked():
    """bar-piston's 178 parameters of segments, links and seal parts cost the
    browser 4-10 s per edit when drawn: the page draws the others first."""
    from pdbfs.models import RIGS
    bar = Workbench("bar-piston")
    names = [c.name for c in bar.shown()]
    assert "piston.L" in names and "oil.k" in names and "hammer.h" in names
    assert not any(".seg" in n or ".link" in n or ".part" in n for n in names)
    assert len(bar.shown(True)) == len(bar.controls) == len(RIGS["bar-piston"]().compile().params) + 1
    assert "178 parameters of repeated parts" in bar.parts_note()
    assert workbench("paper").shown() == workbench("paper").controls
    assert workbench("paper").parts_note() == ""


def test_the_page_s_summary_is_its_backend_s_and_near_a_converged_run(wb):
    """What README states: the page's numbers are rig.simulate's with the
    page's backend, exactly; at the default tolerance they are within 2e-6
    of a run converged at rtol = 1e-12, and the two backends agree to 1e-8
    once both are run at rtol = 1e-10 (restitution 1e-6; their 1e-5 apart at
    the defaults is integration error, not two models)."""
    params = {"oil.k": 1e8}
    rows = dict((k, v) for k, v, _ in wb.outcome({**wb.defaults(), **params})["rows"])
    same = paper_rig().simulate(0.02, params=params, backend=wb.backend).summary()
    ref = paper_rig().simulate(0.02, params=params, backend="c", rtol=1e-12, atol=1e-14).summary()
    for key in ("peak_pressure", "time_of_peak", "pulse_duration", "peak_contact_force",
                "restitution_coefficient"):
        assert rows[key] == same[key], key
        assert rows[key] == pytest.approx(ref[key], rel=2e-6), key
    tight = {b: paper_rig().simulate(0.02, params=params, backend=b, rtol=1e-10,
                                     atol=1e-12).summary() for b in ("casadi", "c")}
    for key in ("peak_pressure", "peak_contact_force", "time_of_peak", "pulse_duration"):
        assert tight["casadi"][key] == pytest.approx(tight["c"][key], rel=1e-8), key
    # the compiled summary's impulses by its own quadrature: 4e-7 (README)
    assert tight["casadi"]["restitution_coefficient"] == pytest.approx(
        tight["c"]["restitution_coefficient"], rel=1e-6)


# -- the page reads like the rest: key settings first, descriptions, numbers to their digits ----

def test_every_rig_s_key_parameters_are_its_own():
    """A declared key parameter the rig does not have would silently drop
    from the page: each is a parameter of the compiled rig."""
    from pdbfs.models import RIGS
    for name, build in RIGS.items():
        rig = build()
        keys = getattr(rig, "key_parameters", ())
        assert keys, name
        names = set(rig.compile().p_names)
        assert set(keys) <= names, (name, set(keys) - names)


def test_the_page_lists_the_key_settings_first_and_the_start_positions_last():
    """The paper's rig opens with what the paper found matters (impact speed
    and its drop height, oil stiffness, seal friction), not frame.s0; each
    component's settings together; start positions and velocities last."""
    from pdbfs.models import RIGS
    assert [c.name for c in workbench("paper").controls][:4] == \
        ["hammer.v0", "hammer.h", "oil.k", "seal.c"]
    assert [c.name for c in workbench("drop").controls][:3] == ["h", "oil.k", "seal.c"]
    assert [c.name for c in workbench("hydraulic-pulse").controls][:4] == \
        ["supply.p0", "valve.A", "drain.A", "chamber.K"]
    start = ("s0", "v0", "p0", "s_rel0")
    for name in ("paper", "drop", "paper-hydraulic", "hydraulic-pulse-line", "split-piston"):
        wb_ = workbench(name)
        names = [c.name for c in wb_.controls]
        keys = [n for n in wb_.rig.key_parameters if n in names]
        assert names[:len(keys)] == keys or names[:len(keys) + 1] == [keys[0], "hammer.h",
                                                                        *keys[1:]], name
        rest = [n for n in names if n not in keys and n != "hammer.h"]
        starts = [n for n in rest if n.rsplit(".", 1)[-1] in start]
        assert rest[len(rest) - len(starts):] == starts, (name, rest)
        owners = [n.split(".", 1)[0] for n in rest[:len(rest) - len(starts)] if "." in n]
        seen = [o for k, o in enumerate(owners) if k == 0 or owners[k - 1] != o]
        assert len(seen) == len(set(seen)), (name, owners)     # each component's together
        assert sorted(names) == sorted(c.name for c in Workbench(name).controls)
        assert set(names) == set(wb_.dae.p_names) | ({"hammer.h"} if wb_.height else set())
    groups = [g for g, _ in workbench("paper").shown_groups()]
    assert groups[0] == "key" and groups[-1] == "start" and "hammer" in groups


def test_curves_are_named_by_their_description_and_unit(wb):
    """The legend says 'contact compressive force [kN]', not 'contact.fc':
    the words of each variable's declared description, and the unit drawn."""
    from pdbfs.app.interact import draw
    dae = paper_rig().compile()
    desc = {v.name: v.description for v in (*dae.x_info, *dae.z_info, *dae.y_info)}
    settings = {"rig": "paper", "values": wb.defaults(), "t_end": 0.02, "method": "auto"}
    fig, summary, _ = draw(settings, [{"label": "pin 1 (defaults)", "values": wb.defaults(),
                                       "t_end": 0.02, "method": "auto"}], None, None, None)
    names = [t["name"] for t in fig["data"] if t.get("showlegend", True)]
    assert names == ["pin 1 (defaults)", "oil pressure [MPa]", "contact compressive force [kN]",
                     "hammer position [mm]", "piston position [mm]", "breech position [mm]"]
    for name, shown in (("oil.pressure", "oil pressure"), ("contact.fc", "compressive force"),
                        ("hammer.s", "position")):
        assert desc[name].lower().startswith(shown), (name, desc[name])
    assert not any("." in n.split(" (")[0] for n in names)      # no raw names
    pins = [t for t in fig["data"] if t.get("legendgroup") == "pin 1 (defaults)"]
    assert len(pins) == 5 and sum(t.get("showlegend", True) for t in pins) == 1
    assert "pin 1 (defaults): contact compressive force" in pins[1]["hovertemplate"]
    # the summary to 5 digits, in MPa and ms
    api = paper_rig().simulate(0.02, backend=wb.backend).summary()
    text = str(summary)
    assert f"{api['peak_pressure'] / 1e6:.5g} MPa" in text
    assert f"{api['time_of_peak'] * 1e3:.5g} ms" in text
    assert f"{api['restitution_coefficient']:.5g}'" in text
    assert f"{api['peak_pressure'] / 1e6:.6g}" not in text


def test_numbers_are_written_to_their_digits():
    from pdbfs.app.numbers import number, quantity, short_description, with_std
    assert number(drop_height(2.73), 4) == "0.38"             # not 0.379992
    assert number(2.228e8) == "2.228e8" and number(2948.4) == "2948.4"
    assert number(8000.0, 3) == "8000" and number(2948.4, 3) == "2950"
    assert number(8e-5) == "8e-5" and number(1e300) == "1e300" and number(-0.0227) == "-0.0227"
    rng = np.random.default_rng(1)
    for x in np.concatenate([10.0 ** rng.uniform(-12, 12, 300), -10.0 ** rng.uniform(-6, 6, 50)]):
        for d in (3, 4, 5, 6):
            assert float(number(x, d)) == float(f"{x:.{d}g}"), (x, d)     # what float() reads
    assert quantity(92117195.11, "Pa") == "92.117 MPa"
    assert quantity(0.0055661419, "s") == "5.5661 ms"
    assert quantity(0.92297916, "1") == "0.92298"
    assert quantity(None, "Pa") == "n/a"
    # a fitted value to the digit its standard deviation allows
    assert with_std(3.00012345e8, 1.234e4) == "3.00012e8 ± 1.2e4"     # to 1e3
    assert with_std(0.61234567, 0.0021) == "0.6123 ± 0.0021"
    assert with_std(0.6, 2.0) == "0.6 ± 2"
    assert with_std(None, 1.0) == "undetermined"
    assert short_description("Compressive force, positive when pushing") == "compressive force"
    assert short_description("Oil column stiffness (unit N/m^n); the paper's k2") == \
        "oil column stiffness"
    assert short_description("RMS of the residual") == "RMS of the residual"


def test_a_slider_s_value_is_the_one_its_field_shows(wb):
    """What is shown is what is simulated: a slider position stands for a
    value rounded to the slider's resolution, not 2.23872e8."""
    k = wb.control("oil.k")
    v = k.slider_value(8.35)
    assert v == 2.239e8
    h = wb.control("hammer.h")
    assert h.slider_value(0.49000000000000005) == 0.49
