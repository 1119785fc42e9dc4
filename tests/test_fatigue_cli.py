"""pdbfs fatigue: a blow against a gun firing. Each figure is checked against
an independent computation (the rig simulated here, the firing read with
numpy, Miner's and Lamé's closed forms), the drop height against the damage
of a blow from it, and bad input against one line and exit status 2."""
import json
import math

import numpy as np
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.fatigue import rainflow
from pdbfs.models import paper_rig

G = 9.80665


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def closed_form_damage(p, m=3.0, ref=70e6, n_ref=1e6, a=0.08, b=0.16):
    """Miner's sum of a pressure sequence's rainflow cycles, by hand: hoop
    stress k p (Lamé), each cycle's range to the m-th power over the curve's."""
    k = (b * b + a * a) / (b * b - a * a)
    cycles = rainflow(p)
    return float(np.sum(cycles["count"] * (k * cycles["range"] / ref) ** m) / n_ref)


def test_the_report_is_the_blow_and_the_firing_computed_independently(capsys):
    code, out, err = run(capsys, "fatigue", "--blows", "20000", "--json")
    assert code in (0, None), err
    r = json.loads(out)
    firing = np.loadtxt(pdbfs.example_data("gun_firing.csv"), delimiter=",", skiprows=1)
    assert r["firing"]["damage"] == pytest.approx(closed_form_damage(firing[:, 1]), rel=1e-12)
    assert r["firing"]["peak_pressure"] == firing[:, 1].max()
    # the blow: the paper rig at its Table 1 speed, on a fine grid here
    res = paper_rig().simulate(0.02, n_out=20001)
    d_blow = closed_form_damage(res["oil.pressure"])
    assert r["blow"]["damage"] == pytest.approx(d_blow, rel=1e-6)
    assert r["blow"]["peak_pressure"] == pytest.approx(res.summary()["peak_pressure"], rel=1e-12)
    assert r["blows_per_firing"] == pytest.approx(r["firing"]["damage"] / d_blow, rel=1e-6)
    assert r["life_blows"] == pytest.approx(1 / d_blow, rel=1e-6)
    assert r["campaign"]["damage"] == pytest.approx(20000 * d_blow, rel=1e-6)
    assert r["campaign"]["firings"] == pytest.approx(20000 * d_blow / r["firing"]["damage"],
                                                     rel=1e-6)


def test_a_blow_from_the_equal_drop_height_does_a_firings_damage(capsys):
    code, out, err = run(capsys, "fatigue", "--json")
    assert code in (0, None), err
    r = json.loads(out)
    h = r["equal_height"]
    assert h["parameter"] == "hammer.v0" and h["value"] == pytest.approx(math.sqrt(2 * G * h["height"]))
    res = paper_rig().simulate(0.02, n_out=20001, params={"hammer.v0": h["value"]})
    assert closed_form_damage(res["oil.pressure"]) == pytest.approx(r["firing"]["damage"], rel=1e-6)
    # the blow equal to a firing peaks near the firing's peak (the damage goes
    # with the cube of the range), higher than the paper's blow
    assert 0.9 < res.summary()["peak_pressure"] / r["firing"]["peak_pressure"] < 1.1


def test_the_table_shows_every_figure(capsys):
    code, out, err = run(capsys, "fatigue", "--blows", "1000")
    assert code in (0, None), err
    for words in ("one blow", "one firing", "blows that stand for one firing",
                  "drop height of a blow = a firing", "hammer.v0 =", "predicted life",
                  "campaign of 1000 blows"):
        assert words in out, (words, out)


def test_a_height_out_of_reach_or_a_rig_without_one_is_said(capsys):
    code, out, err = run(capsys, "fatigue", "--heights", "0.01:0.05", "--json")
    assert code in (0, None), err
    r = json.loads(out)
    assert r["equal_height"] is None and "above what blows from 0.01 to 0.05 m do" in \
        r["equal_height_note"]
    code, out, err = run(capsys, "fatigue", "--rig", "hydraulic-pulse")
    assert code in (0, None), err
    assert "n/a: rig pdbfs_hydraulic_pulse has no drop height or impact speed" in out


def test_the_breech_and_the_curve_given_are_used(capsys):
    """A thinner wall and a steeper curve: the firing's damage by hand."""
    code, out, err = run(capsys, "fatigue", "--breech", "0.1:0.15", "--sn", "5:300e6:2e5:20e6",
                         "--heights", "0.1:0.2", "--json")
    assert code in (0, None), err
    r = json.loads(out)
    p = np.loadtxt(pdbfs.example_data("gun_firing.csv"), delimiter=",", skiprows=1)[:, 1]
    k = (0.15 ** 2 + 0.1 ** 2) / (0.15 ** 2 - 0.1 ** 2)
    cycles = rainflow(p)
    s = k * cycles["range"]
    want = float(np.sum(np.where(s > 20e6, cycles["count"] * (s / 300e6) ** 5, 0.0)) / 2e5)
    assert r["firing"]["damage"] == pytest.approx(want, rel=1e-12)
    assert r["breech"]["bore_factor"] == pytest.approx(k, rel=1e-14)


@pytest.mark.parametrize("argv, culprit", [
    (["--sn", "0:7e7:1e6"], "SNCurve: m = 0 must be positive"),
    (["--sn=-2:7e7:1e6"], "SNCurve: m = -2 must be positive"),
    (["--sn", "3:7e7"], "--sn 3:7e7: expected M:RANGE:CYCLES[:LIMIT]"),
    (["--breech", "0.2:0.1"], "outer_radius = 0.1 m must be above inner_radius = 0.2 m"),
    (["--heights", "2:1"], "--heights 2:1: give 0 < LO < HI"),
    (["--blows", "0"], "--blows 0: a campaign has 1 blow or more"),
    (["--firing", "missing.csv"], "--firing file 'missing.csv': no such file"),
    (["--firing", "one_column.csv"], "needs two columns, time (s) and the signal"),
    (["--firing", "force.csv"], "is in N, not a pressure"),
    (["--firing", "untimed.csv"], "no time column"),
    (["--set", "nope=1"], "unknown parameter 'nope'"),
    (["--t-end", "0.004"], "the pulse is still running at t_end = 0.004 s"),
])
def test_bad_input_is_one_line_with_status_2(capsys, tmp_path, argv, culprit):
    (tmp_path / "one_column.csv").write_text("pressure [Pa]\n" + "1e6\n" * 20)
    (tmp_path / "force.csv").write_text("time [s],force [N]\n" + "".join(
        f"{k * 1e-4},{k}\n" for k in range(20)))
    (tmp_path / "untimed.csv").write_text("pressure [MPa],other [MPa]\n" + "".join(
        f"{k},{k}\n" for k in range(20)))
    code, out, err = run(capsys, "fatigue", *argv)
    assert code == 2 and culprit in err and err.count("\n") == 1 and not out, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["force.csv", "one_column.csv",
                                                          "untimed.csv"]


def test_a_damage_that_does_not_grow_with_the_height_gives_no_height():
    """The drop rig over a fixed horizon: a higher drop strikes later and its
    rebounds fall in or out of the run, so the run's damage does not grow
    with the height; the search says so instead of picking a root."""
    from pdbfs.models import drop_rig
    from pdbfs.studies import height_for_damage
    found = height_for_damage(drop_rig(), 3e-5, heights=(0.2, 0.6), t_end=1.0)
    assert found.height is None and "does not grow with the drop height" in found.note
    d = found.damages
    assert found.parameter == "h" and any(b <= a for a, b in zip(d, d[1:]))
