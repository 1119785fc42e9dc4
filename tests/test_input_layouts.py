"""A trace is read in one documented layout, never transposed silently:
(t, u) as a pair or a (2, n) array, or named columns (a dict, a
DataFrame); rows of (t, u) and a 2 x 2 that reads both ways are refused.
A CSV's time column is the one its header names, wherever it stands;
compressed files and comment lines are read; a bad cell is shown as the
file has it. A free mass pushed by F(t) = 2 + 3 t from rest: x(1) =
1 + 0.5 = 1.5 m (m = 1 kg), read every way."""
import bz2
import gzip

import numpy as np
import pandas as pd
import pytest

import pdbfs
from pdbfs.cli import main
from pdbfs.cli.inputs import read_input
from pdbfs.components import Mass, SignalForce
from pdbfs.components import blocks as B
from pdbfs.studies.fitting.traces import read_trace

X1 = 1.0 + 0.5          # m: x(1) of x'' = 2 + 3 t from rest


class Free(pdbfs.Rig):
    """A free mass of 1 kg pushed by the input ``force``."""

    def declare(self):
        self.body = Mass(m=1.0)
        self.push = SignalForce()
        self.force = B.Input("N")
        self.connect(self.body.flange_b, self.push.flange)
        self.connect(self.force.y, self.push.u)


def x1(given):
    return Free().simulate(1.0, n_out=11, inputs={"force": given}, rtol=1e-12, atol=1e-14)[
        "body.s"][-1]


@pytest.mark.parametrize("given", [
    ([0.0, 1.0], [2.0, 5.0]),                                # the pair (t, u)
    (np.array([0.0, 0.5, 1.0]), np.array([2.0, 3.5, 5.0])),
    [[0.0, 0.5, 1.0], [2.0, 3.5, 5.0]],                      # a list of the two
    np.array([[0.0, 0.5, 1.0], [2.0, 3.5, 5.0]]),            # shape (2, n)
    {"t": [0.0, 1.0], "force": [2.0, 5.0]},
    {"time": [0.0, 1.0], "u": [2.0, 5.0]},                   # the only other column
    pd.DataFrame({"force": [2.0, 3.5, 5.0], "time": [0.0, 0.5, 1.0]}),
])
def test_the_documented_layouts_give_the_same_run(given):
    assert x1(given) == pytest.approx(X1, rel=1e-9)


@pytest.mark.parametrize("given, culprit", [
    ([(0, 2), (1, 5)], "reads both as (t, u) = ([0, 2], [1, 5]) and as rows (t = [0, 1], "
                       "u = [2, 5])"),
    (np.array([[0, 2], [1, 5]]), "an array of shape (2, 2): reads both"),
    ([(0, 2), (0.5, 3.5), (1, 5)], "3 rows of (time, value); a trace is (t, u)"),
    (np.array([[0, 2], [0.5, 3.5], [1, 5]]), "shape (3, 2): give a trace (t, u), a row of times "
                                             "and a row of values (shape (2, n)); for rows"),
    ({"t": [0, 1], "a": [2, 5], "b": [2, 5]}, "name the value column 'force'"),
    ({"x": [0, 1], "force": [2, 5]}, "name one time column 't' or 'time'"),
])
def test_rows_and_ambiguous_layouts_are_refused(given, culprit):
    """Read as (t, u) these rows would be another trace and a wrong run (a
    list of the two pairs gave x(1) = 0.833 m instead of 1.5 m)."""
    with pytest.raises(pdbfs.ParameterError) as err:
        x1(given)
    assert culprit in str(err.value) and "\n" not in str(err.value)


ROWS = "".join(f"{t:g},{2 + 3 * t:g}\n" for t in np.linspace(0, 1, 11))
SWAPPED = "".join(f"{2 + 3 * t:g},{t:g}\n" for t in np.linspace(0, 1, 11))


@pytest.mark.parametrize("name, text", [
    ("swapped.csv", "force,time\n" + SWAPPED),               # the header names time second
    ("ms.csv", "force [N];time [ms]\n" + "".join(f"{2 + 3 * t:g};{1000 * t:g}\n"
                                                 for t in np.linspace(0, 1, 11))),
    ("comments.csv", "# recorded 2026-11-30\n# bench 3\ntime [s],force [N]\n" + ROWS),
    ("plain.csv", ROWS),                                     # no header: time first
    ("time_s.csv", "time_s,force\n" + ROWS),
])
def test_an_input_file_is_read_by_its_header(tmp_path, name, text):
    (tmp_path / name).write_text(text)
    t, u = read_input(tmp_path / name, "force", "N")
    assert np.allclose(t, np.linspace(0, 1, 11), rtol=0, atol=1e-12)
    assert np.allclose(u, 2 + 3 * t, rtol=1e-12)
    assert x1((t, u)) == pytest.approx(X1, rel=1e-9)


@pytest.mark.parametrize("suffix, opener", [(".csv.gz", gzip.open), (".csv.bz2", bz2.open)])
def test_compressed_files_are_read(tmp_path, suffix, opener):
    path = tmp_path / f"force{suffix}"
    with opener(path, "wt") as fh:
        fh.write("# a comment first\ntime;force\n" + ROWS.replace(",", ";"))
    t, u = read_input(path, "force", "N")
    assert np.allclose(u, 2 + 3 * t, rtol=1e-12) and t.size == 11
    trace = read_trace(path)
    assert trace.name == "force" and np.array_equal(trace.t, t)


@pytest.mark.parametrize("text, culprit", [
    ("a,b\n" + ROWS, "no time column among 'a', 'b'; name one 'time'"),
    ("time,force\n0,2\n0.5,\"3,5\"\n1,5\n", "column force, data row 2: 3,5 is not a number"),
    ("time,force\n0,2\n0.5, abc\n1,5\n", "column force, data row 2: abc is not a number"),
    ("time [kPa],force\n" + ROWS, "the column 'time [kPa]' must be time"),
    ("# only a comment\n", "no table in it"),
])
def test_bad_input_files_are_refused_in_one_line(tmp_path, capsys, text, culprit):
    (tmp_path / "f.csv").write_text(text)
    with pytest.raises(pdbfs.DataError) as err:
        read_input(tmp_path / "f.csv", "force", "N")
    assert culprit in str(err.value) and "\n" not in str(err.value)
    assert "'abc'" not in str(err.value)             # the cell as the file has it


def test_the_command_line_reads_a_file_headed_force_then_time(tmp_path, capsys, monkeypatch):
    from pdbfs.models import RIGS
    monkeypatch.setitem(RIGS, "free", Free)
    (tmp_path / "f.csv").write_text("force,time\n" + SWAPPED)
    out = tmp_path / "out"
    assert main(["simulate", "--rig", "free", "--t-end", "1", "--input", f"force={tmp_path / 'f.csv'}",
                 "--out", str(out)]) in (0, None)
    res = pd.read_csv(out / "results.csv")
    assert res["body.s [m]"].iloc[-1] == pytest.approx(X1, rel=1e-6)
