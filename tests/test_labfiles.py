"""Measured traces from data-acquisition files (pdbfs[lab]): a real NI TDMS
file written by npTDMS and a real ASAM MDF4 file written by asammdf, read
through calibrate --trace, simulate --input and fatigue --firing, each
giving what the same samples give from a CSV file; and the files that are
not traces refused in one line."""
import json
import sys

import numpy as np
import pytest

from pdbfs.cli import main
from pdbfs.models import RIGS, paper_rig

from input_rigs import CommandedPulse

nptdms = pytest.importorskip("nptdms")
asammdf = pytest.importorskip("asammdf")

V0 = 3.1                        # the impact speed the "measured" trace was made at, m/s


def measured(n=1501, dt=1e-5):
    """A trace of the paper rig at V0: its times (s) and pressures (Pa)."""
    t = np.arange(n) * dt
    return t, paper_rig().simulate(float(t[-1]), t_out=t, params={"hammer.v0": V0})["oil.pressure"]


def write_tdms(path, channels, group="DAQ", time=None, waveform=None):
    """A TDMS file of {name: (values, unit)}: times as a time channel, or as
    waveform properties (t0, dt), or none."""
    from nptdms import ChannelObject, GroupObject, TdmsWriter
    objects = [GroupObject(group)]
    if time is not None:
        objects.append(ChannelObject(group, "Time", time, properties={"unit_string": "s"}))
    for name, (y, unit) in channels.items():
        props = {"unit_string": unit} if unit else {}
        if waveform is not None:
            props.update(wf_start_offset=waveform[0], wf_increment=waveform[1])
        objects.append(ChannelObject(group, name, y, properties=props))
    with TdmsWriter(str(path)) as w:
        w.write_segment(objects)


def write_mdf(path, groups):
    """An MDF4 file with one channel group per item of ``groups``: [(t, {name: (y, unit)})]."""
    from asammdf import MDF, Signal
    mdf = MDF(version="4.10")
    for t, chans in groups:
        mdf.append([Signal(np.asarray(y), np.asarray(t), name=n, unit=u) for n, (y, u) in
                    chans.items()])
    mdf.save(str(path), overwrite=True)
    mdf.close()


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_calibrate_reads_a_tdms_and_an_mdf4_trace_as_it_reads_the_csv(tmp_path, capsys):
    """The fit to each file is the fit to the CSV of the same samples (MPa in
    the TDMS file, bar in the MDF file: converted), and it finds V0."""
    t, p = measured()
    np.savetxt(tmp_path / "m.csv", np.column_stack([t, p]), delimiter=",",
               header="time [s],oil.pressure [Pa]", comments="")
    write_tdms(tmp_path / "m.tdms", {"oil.pressure": (p / 1e6, "MPa")}, waveform=(0.0, 1e-5))
    write_mdf(tmp_path / "m.mf4", [(t, {"oil.pressure": (p / 1e5, "bar")}),
                                   (t[::3], {"accel": (np.sin(t[::3]), "m/s2")})])
    fits = {}
    for name in ("m.csv", "m.tdms", "m.mf4"):
        code, out, err = run(capsys, "calibrate", "--trace", str(tmp_path / name), "--free",
                             "hammer.v0", "--starts", "1", "--json")
        assert code in (0, None), err
        fits[name] = json.loads(out)["params"]["hammer.v0"]
    assert fits["m.csv"] == pytest.approx(V0, rel=1e-6)
    assert fits["m.tdms"] == pytest.approx(fits["m.csv"], rel=1e-9)
    assert fits["m.mf4"] == pytest.approx(fits["m.csv"], rel=1e-9)


def test_simulate_takes_an_input_from_a_tdms_file(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(RIGS, "commanded", CommandedPulse)
    t = np.linspace(0.0, 0.02, 81)
    u = np.clip(np.sin(np.pi * t / 0.02) * 1.2, 0.0, 1.0)
    np.savetxt(tmp_path / "c.csv", np.column_stack([t, u]), delimiter=",",
               header="time [s],command", comments="")
    write_tdms(tmp_path / "c.tdms", {"command": (u, ""), "spare": (u * 0, "V")}, time=t)
    got = {}
    for name in ("c.csv", "c.tdms"):
        code, out, err = run(capsys, "simulate", "--rig", "commanded", "--input",
                             f"command={tmp_path / name}", "--t-end", "0.02", "--json")
        assert code in (0, None), err
        got[name] = json.loads(out)["peak_pressure"]
    assert got["c.tdms"] == got["c.csv"] > 1e6


def test_fatigue_reads_the_firing_from_an_mdf4_file(tmp_path, capsys):
    """The shipped firing written to an MDF4 file (in MPa, beside a channel on
    another clock): the same firing damage as the CSV it came from."""
    import pdbfs
    data = np.loadtxt(pdbfs.example_data("gun_firing.csv"), delimiter=",", skiprows=1)
    write_mdf(tmp_path / "f.mf4", [(data[:, 0], {"chamber": (data[:, 1] / 1e6, "MPa")}),
                                   (data[::4, 0], {"strain": (data[::4, 1] * 0, "1")})])
    code, out, err = run(capsys, "fatigue", "--json")
    assert code in (0, None), err
    csv = json.loads(out)["firing"]["damage"]
    code, out, err = run(capsys, "fatigue", "--firing", str(tmp_path / "f.mf4"), "--signal",
                         "chamber", "--json")
    assert code in (0, None), err
    assert json.loads(out)["firing"]["damage"] == pytest.approx(csv, rel=1e-12)


def test_bad_lab_files_are_one_line_with_status_2(tmp_path, capsys):
    t, p = measured(200)
    write_tdms(tmp_path / "untimed.tdms", {"p": (p, "Pa")})
    write_tdms(tmp_path / "two.tdms", {"p": (p, "Pa"), "q": (p, "Pa")}, waveform=(0.0, 1e-5))
    write_mdf(tmp_path / "clocks.mf4", [(t, {"p": (p, "Pa")}), (t[::2], {"q": (p[::2], "Pa")})])
    (tmp_path / "text.tdms").write_text("time,p\n0,1\n")
    cases = [("untimed.tdms", [], "no times: no time channel and no waveform timing"),
             ("two.tdms", [], "2 signal columns ('p', 'q')"),
             ("two.tdms", ["--signal", "r"], "no column 'r' among 'p', 'q'"),
             ("clocks.mf4", [], "its channels have 2 time bases (p; q); name the channel"),
             ("text.tdms", [], "not an NI TDMS file")]
    for name, extra, culprit in cases:
        code, out, err = run(capsys, "fatigue", "--firing", str(tmp_path / name), *extra)
        assert code == 2 and culprit in err and err.count("\n") == 1 and not out, (name, err)


def test_without_the_extra_a_lab_file_is_one_line_naming_it(tmp_path, capsys, monkeypatch):
    t, p = measured(200)
    write_tdms(tmp_path / "m.tdms", {"p": (p, "Pa")}, waveform=(0.0, 1e-5))
    monkeypatch.setitem(sys.modules, "nptdms", None)        # as if not installed
    code, out, err = run(capsys, "fatigue", "--firing", str(tmp_path / "m.tdms"))
    assert code == 2 and err.count("\n") == 1 and not out, err
    assert "pip install 'pdbfs[lab]'" in err and "nptdms" in err and "TDMS" in err
