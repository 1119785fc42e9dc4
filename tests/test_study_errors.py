"""Bad input to calibrate, design and design-map: one line naming the
culprit, exit status 2, nothing written."""
import numpy as np
import pytest

from pdbfs.cli import main
from pdbfs.models import paper_rig


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """A short, valid trace of the paper rig."""
    path = tmp_path_factory.mktemp("trace") / "good.csv"
    res = paper_rig().simulate(0.012, n_out=241)
    np.savetxt(path, np.column_stack([res.t, res["oil.pressure"]]), delimiter=",",
               header="time,pressure", comments="")
    return path


def fails(capsys, argv, *fragments):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("pdbfs: error:"), err
    for f in fragments:
        assert f in err, (f, err)
    return err


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


@pytest.mark.parametrize("content, fragments", [
    ("", ("empty",)),
    ("time,pressure\n", ("no data rows",)),
    ("time,pressure\n0,1\n1,x\n" + "".join(f"{k},1\n" for k in range(2, 20)), ("column pressure, data row 2: x is not a number",)),
    ("time,pressure\n" + "".join(f"{k},1\n" for k in range(12)) + "5,1\n", ("increase strictly", "row 13")),
    ("time,pressure\n" + "".join(f"{k},1\n" for k in range(12)) + "12,nan\n", ("NaN",)),
    ("time,pressure\n0,1\n1,2\n2,3\n", ("3 data rows", "at least 10")),
    ("time\n0\n1\n", ("two columns",)),
])
def test_bad_trace_files(tmp_path, capsys, content, fragments):
    path = write(tmp_path, "trace.csv", content)
    out = tmp_path / "out"
    fails(capsys, ["calibrate", "--trace", str(path), "--free", "oil.k", "--out", str(out)],
          "trace.csv", *fragments)
    assert not out.exists()


def test_missing_trace_file(tmp_path, capsys):
    fails(capsys, ["calibrate", "--trace", str(tmp_path / "nope.csv"), "--free", "oil.k"],
          "nope.csv", "no such file")


@pytest.mark.parametrize("args, fragments", [
    (["--free", "oil.kk"], ("oil.kk", "did you mean oil.k")),
    (["--free", "oil.k", "--signal", "oil.presure"], ("oil.presure", "oil.pressure")),
    (["--free", "oil.k,oil.k"], ("oil.k", "twice")),
    (["--free", "oil.k", "--set", "oil.k=3e8"], ("oil.k", "both free and fixed")),
    (["--free", "oil.k", "--bounds", "oil.k=5e8:1e8"], ("bounds of oil.k",)),
    (["--free", "oil.k", "--bounds", "seal.c=1:2"], ("seal.c", "not a free parameter")),
    (["--free", "contact.D", "--rig", "paper-ln"], ("contact.D", "computed from other parameters")),
])
def test_bad_free_parameters(good, tmp_path, capsys, args, fragments):
    out = tmp_path / "out"
    fails(capsys, ["calibrate", "--trace", str(good), "--out", str(out)] + args, *fragments)
    assert not out.exists()


def test_a_failed_design_leaves_earlier_results_alone(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["design", "--peak", "1.2e8", "--free", "hammer.v0", "--out", str(out)]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {"design.png", "design.csv", "design.json"}
    capsys.readouterr()
    fails(capsys, ["design", "--peak", "6e8", "--free", "hammer.v0", "--bounds", "hammer.v0=1:6",
                   "--out", str(out)], "not reached", "hammer.v0 at its upper bound 6")
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


@pytest.mark.parametrize("args, fragments", [
    (["design", "--free", "hammer.v0"], ("no design target",)),
    (["design", "--peak", "-5", "--free", "hammer.v0"], ("peak_pressure", "positive")),
    (["design", "--peak", "1e8", "--target", "t.csv", "--free", "hammer.v0"], ("not both",)),
    (["design-map", "--x", "hammer.v0=6:1", "--y", "oil.k=1e8:1e9"], ("hammer.v0", "below")),
    (["design-map", "--x", "hammer.v0=1:6", "--y", "oil.k"], ("NAME=LO:HI",)),
    (["design-map", "--x", "hammer.v0=1:6", "--y", "oil.k=1e8:1e9", "--n", "1"], ("n = 1",)),
])
def test_bad_design_input(capsys, args, fragments):
    fails(capsys, args, *fragments)
