"""pdbfs campaign and the campaign in pdbfs fatigue: the JSON's blows are the
API's, a campaign stopped half-way resumes to the same blows as one run
whole, pdbfs fatigue reads a saved campaign or runs one, and bad input gets
one line, exit status 2 and no file, before any blow is run."""
import json

import numpy as np
import pytest

from pdbfs.cli import main
from pdbfs.errors import ParameterError
from pdbfs.models import paper_thermal_rig
from pdbfs.studies.campaign import HoldPeak, campaign


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_the_json_lists_every_blow_as_the_api_runs_it(capsys):
    code, out, err = run(capsys, "campaign", "--rig", "paper-thermal", "--blows", "60",
                         "--period", "10", "--json")
    assert code == 0, err
    doc = json.loads(out)
    api = campaign(paper_thermal_rig(), 60, 10.0)
    assert len(doc["blows"]) == 60
    for k in ("peak_pressure", "oil_temperature", "damage", "energy_dissipated"):
        assert [b[k] for b in doc["blows"]] == api.table[k].tolist(), k
    assert doc["blows"][0]["oil_temperature"] == 293.15 < doc["blows"][-1]["oil_temperature"]
    assert doc["totals"]["life_blows"] == pytest.approx(api.life, rel=1e-15)
    assert abs(doc["totals"]["heat_balance"]) < 1e-6


STOP = []


def _held(blows):
    """Hold the peak in a band; once asked (STOP), stop the campaign after 120
    blows, as Ctrl-C would."""
    if len(blows) == 120 and STOP:
        STOP.pop()
        raise KeyboardInterrupt
    return HoldPeak(91.9e6, 92.0e6, parameter="hammer.v0", exponent=1.0)(blows)


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_a_stopped_campaign_resumes_to_the_blows_of_one_run_whole(tmp_path, fmt):
    """Stopped at blow 121, two chunks of 50 saved; run again, it resumes at
    blow 101 (its rule asked from the saved blows) and ends as the campaign
    run whole, to the last bit."""
    if fmt == "parquet":
        pytest.importorskip("pyarrow")
    rig = paper_thermal_rig()
    whole = campaign(rig, 300, 10.0, rule=_held, check_every=50)
    assert whole.table["hammer.v0"].nunique() > 1            # the rule acted
    out = tmp_path / "c"
    STOP.append(1)
    with pytest.raises(KeyboardInterrupt):
        campaign(rig, 300, 10.0, rule=_held, out=out, chunk_size=50, format=fmt, check_every=50)
    with pytest.raises(ParameterError, match="holds another campaign"):
        campaign(rig, 300, 11.0, rule=_held, out=out, chunk_size=50, format=fmt, check_every=50)
    again = campaign(rig, 300, 10.0, rule=_held, out=out, chunk_size=50, format=fmt,
                     check_every=50)
    assert again.computed == 200
    assert list(again.table.columns) == list(whole.table.columns)
    for k in whole.table.columns:
        assert np.array_equal(again.table[k].to_numpy(dtype=float),
                              whole.table[k].to_numpy(dtype=float), equal_nan=True), k
    assert again.final == whole.final


def test_the_command_resumes_and_fatigue_reads_what_it_saved(capsys, tmp_path):
    out = tmp_path / "camp"
    argv = ("campaign", "--rig", "paper-thermal", "--blows", "150", "--period", "10",
            "--chunk", "100", "--out", str(out), "--format", "csv")
    code, text, err = run(capsys, *argv)
    assert code == 0, err
    assert (out / "campaign.csv").is_file() and (out / "campaign.png").is_file()
    assert "150 computed" in text and "balance" in text
    (out / "chunks" / "chunk-000001.csv").unlink()          # the last 50 blows lost
    code, text, err = run(capsys, *argv)
    assert code == 0 and "50 computed" in text and "100 found done" in text, err
    code, text, err = run(capsys, "fatigue", "--rig", "paper-thermal", "--campaign", str(out),
                          "--json")
    assert code == 0, err
    doc = json.loads(text)["campaign"]
    saved = np.loadtxt(out / "campaign.csv", delimiter=",", skiprows=1, usecols=[-1])
    header = (out / "campaign.csv").read_text().splitlines()[0].split(",")
    assert header[-1] == "damage"
    assert doc["blows"] == 150 and doc["damage"] == pytest.approx(saved.sum(), rel=1e-12)
    assert doc["blows_per_firing"] == pytest.approx(
        json.loads(text)["firing"]["damage"] / saved.mean(), rel=1e-12)


def test_fatigue_runs_the_campaign_with_a_period(capsys):
    code, text, err = run(capsys, "fatigue", "--rig", "paper-thermal", "--blows", "80",
                          "--period", "10", "--json")
    assert code == 0, err
    doc = json.loads(text)
    api = campaign(paper_thermal_rig(), 80, 10.0)
    assert doc["campaign"]["life_blows"] == pytest.approx(api.life, rel=1e-12)
    assert doc["campaign"]["oil_temperature_last"] > doc["campaign"]["oil_temperature_first"]
    # --blows alone: the blows alike, as before
    code, text, err = run(capsys, "fatigue", "--blows", "80", "--json")
    assert json.loads(text)["campaign"]["damage"] == pytest.approx(
        80 * json.loads(text)["blow"]["damage"], rel=1e-12)


@pytest.mark.parametrize("extra,culprit", [
    (["--period", "-10"], "period"),
    (["--period", "0"], "period"),
    (["--period", "nan"], "period"),
    (["--period", "0.01"], "period"),                       # shorter than a blow
    (["--blows", "0"], "blows"),
    (["--rule", "hold-pressure:1:2"], "unknown rule"),
    (["--rule", "hold-peak:9e7"], "hold-peak"),
    (["--rule", "hold-peak:9e7:8e7"], "hold-peak"),
    (["--temperature", "oil_heat.T=300"], "no thermal network"),
    (["--oil", "oil_heat.T"], "no thermal network"),
    (["--damage", "peak", "--check-every", "-1"], "check_every"),
    (["--set", "hammer.v9=1"], "hammer.v9"),
    (["--schedule", "SHORT"], "schedule"),
    (["--schedule", "MISSING"], "schedule"),
    (["--chunk", "0"], "chunk_size"),
])
def test_bad_input_gets_one_line_and_status_2_and_writes_nothing(capsys, tmp_path, extra,
                                                                    culprit):
    short = tmp_path / "short.csv"
    short.write_text("hammer.v0\n2.5\n2.6\n")
    extra = [str(short) if e == "SHORT" else str(tmp_path / "none.csv") if e == "MISSING"
             else e for e in extra]
    argv = ["campaign", "--rig", "paper", "--blows", "5", "--period", "10",
            "--out", str(tmp_path / "out")]
    for k in range(0, len(extra), 2):                        # the bad value replaces the good
        if extra[k] in argv:
            argv[argv.index(extra[k]) + 1] = extra[k + 1]
        else:
            argv += extra[k:k + 2]
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error:") and culprit in lines[0], err
    assert not (tmp_path / "out").exists()


def test_bad_input_to_the_thermal_rig_and_to_fatigue(capsys, tmp_path):
    for argv, culprit in (
            (["campaign", "--rig", "paper-thermal", "--blows", "5", "--period", "10",
              "--temperature", "oil.T=300"], "heat capacitor"),
            (["campaign", "--rig", "paper-thermal", "--blows", "5", "--period", "10",
              "--temperature", "oil_heat.T=-3"], "oil_heat.T"),
            (["campaign", "--rig", "paper-thermal", "--blows", "5", "--period", "10",
              "--schedule", str(tmp_path / "room.csv")], "thermal network"),
            (["fatigue", "--period", "10"], "--blows"),
            (["fatigue", "--blows", "5", "--period", "-1"], "period"),
            (["fatigue", "--campaign", str(tmp_path)], "no campaign")):
        (tmp_path / "room.csv").write_text("room.T\n" + "300\n" * 5)
        code, out, err = run(capsys, *argv)
        lines = err.strip().splitlines()
        assert code == 2 and out == "" and len(lines) == 1 and culprit in lines[0], (argv, err)


def test_ctrl_c_keeps_the_saved_blows_and_says_how_to_go_on(tmp_path):
    """Ctrl-C in a long campaign: status 130, one line naming the blows saved
    (whole chunks, as many as the folder holds) and how to resume."""
    import re
    import signal
    import subprocess
    import sys
    import time
    p = subprocess.Popen([sys.executable, "-m", "pdbfs.cli", "campaign", "--rig", "paper-thermal",
                          "--blows", "500000", "--period", "10", "--chunk", "500", "--out", "o",
                          "--format", "csv"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True, cwd=tmp_path)
    deadline = time.time() + 120
    while time.time() < deadline and len(_chunks(tmp_path / "o")) < 2:
        time.sleep(0.2)
    assert p.poll() is None, "the campaign ended before Ctrl-C"
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert p.returncode == 130, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    m = re.fullmatch(r"pdbfs: interrupted: (\d+) of 500000 blows are saved in o; the same "
                     r"command resumes from there", lines[0])
    assert m, lines[0]
    chunks = _chunks(tmp_path / "o")
    assert int(m.group(1)) == 500 * len(chunks) >= 1000
    assert sorted(p.name for p in (tmp_path / "o" / "chunks").iterdir()) == chunks  # nothing half
    last = (tmp_path / "o" / "chunks" / chunks[-1]).read_text().splitlines()
    assert len(last) == 501 and last[-1].startswith(f"{int(m.group(1))},")


def _chunks(folder):
    """The complete chunk files of a campaign's folder, by name."""
    import re
    d = folder / "chunks"
    return sorted(p.name for p in d.iterdir() if re.fullmatch(r"chunk-\d{6}\.csv", p.name)) \
        if d.is_dir() else []
