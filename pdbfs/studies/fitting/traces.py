"""Measured traces and target curves: a time column and a signal column,
read from a CSV file (units in the header converted to SI, the column chosen
by name), checked before anything is fitted to them."""
from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdbfs.errors import DataError, ParameterError

from ..labfiles import is_lab_file, read_lab_table

#: fewer samples than this cannot carry a pulse, whatever is fitted
MIN_POINTS = 10


#: units a trace's header may give, to SI: (factor, SI unit)
UNITS = {
    "s": (1.0, "s"), "ms": (1e-3, "s"), "us": (1e-6, "s"), "µs": (1e-6, "s"), "μs": (1e-6, "s"),
    "Pa": (1.0, "Pa"), "kPa": (1e3, "Pa"), "MPa": (1e6, "Pa"), "GPa": (1e9, "Pa"),
    "bar": (1e5, "Pa"), "psi": (6894.757293168361, "Pa"),
    "N": (1.0, "N"), "kN": (1e3, "N"), "MN": (1e6, "N"),
    "m": (1.0, "m"), "mm": (1e-3, "m"), "um": (1e-6, "m"), "µm": (1e-6, "m"),
    "m/s": (1.0, "m/s"), "1": (1.0, "1"),
}
_UNIT_IN_NAME = re.compile(r"^\s*(?P<name>.*?)\s*[\[(](?P<unit>[^\])]*)[\])]\s*$")


@dataclass(frozen=True)
class Trace:
    """Samples ``y`` (in the signal's SI unit) at strictly increasing times ``t`` (s)."""

    t: np.ndarray
    y: np.ndarray
    source: str = "trace"
    name: str = ""          # the signal column's name (its unit stripped), if read from a file
    unit: str = ""          # the signal's SI unit, if the header gave one
    time_unit: str = "s"    # the unit a file's header gave the time in ("" if none)

    def __len__(self):
        return len(self.t)

    @property
    def span(self) -> float:
        """The time the trace covers, s."""
        return float(self.t[-1] - self.t[0])


def split_header(label) -> tuple[str, str | None]:
    """'oil.pressure [kPa]' -> ('oil.pressure', 'kPa'); no unit -> (label, None)."""
    m = _UNIT_IN_NAME.match(str(label))
    if m:
        return m.group("name").strip(), m.group("unit").strip()
    return str(label).strip(), None


def to_si(unit, where, column) -> tuple[float, str]:
    """(factor to SI, SI unit) of a column's ``unit``; an unknown unit is a DataError naming ``where``."""
    if unit is None:
        return 1.0, ""
    if unit not in UNITS:
        raise DataError(f"{where}: column {column!r}: unknown unit {unit!r}; known units: "
                        f"{', '.join(UNITS)}")
    return UNITS[unit]


def read_trace(path: str | os.PathLike, what: str = "trace", signal: str | None = None) -> Trace:
    """Read a CSV trace: time in the first column, then the signal. The
    delimiter is sniffed (comma, semicolon, tab or spaces). A header is
    optional; where it gives units (``time [ms]``, ``oil.pressure [kPa]``)
    they are converted to SI, and an unknown unit is refused. With more than
    two columns, ``signal`` names the one to use (pdbfs's own results.csv
    works: its header is ``name [unit]``). DataError, naming the file, for
    anything else."""
    import pandas as pd
    p = Path(path)
    where = f"{what} file {str(path)!r}"
    if not p.is_file():
        raise DataError(f"{where}: no such file")
    if p.stat().st_size == 0:
        raise DataError(f"{where}: the file is empty")
    df = read_table(p, where, signal)
    if df.shape[1] < 2:
        raise DataError(f"{where}: needs two columns, time (s) and the signal; found "
                        f"{df.shape[1]} ({', '.join(map(str, df.columns)) or 'none'})")
    if len(df) == 0:
        raise DataError(f"{where}: a header but no data rows")
    j = _signal_column(df, signal, where)
    cols = []
    for k in (0, j):
        col = pd.to_numeric(df.iloc[:, k], errors="coerce")
        bad = col.isna() & df.iloc[:, k].notna() & (df.iloc[:, k].astype(str).str.strip() != "")
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise DataError(f"{where}: column {df.columns[k]!r}, data row {row + 1}: "
                            f"{df.iloc[row, k]!r} is not a number")
        cols.append(col.to_numpy(dtype=float))
    t_name, t_unit = split_header(df.columns[0])
    y_name, y_unit = split_header(df.columns[j])
    t_factor, t_si = to_si(t_unit, where, df.columns[0])
    if t_unit is not None and t_si != "s":
        raise DataError(f"{where}: the first column {df.columns[0]!r} must be time; its unit "
                        f"{t_unit!r} is not one of time (s, ms, us)")
    y_factor, y_si = to_si(y_unit, where, df.columns[j])
    trace = check_trace(cols[0] * t_factor, cols[1] * y_factor, where, name=y_name)
    return Trace(trace.t, trace.y, where, y_name, y_si, t_unit or "")


def read_table(path: Path, where: str, signal: str | None = None):
    """The CSV table of ``path`` as a DataFrame: its delimiter sniffed, its
    header optional (without one, the columns are "column 1", ...); a file
    that is no table is a DataError naming ``where``. A TDMS or MDF file is
    read as the same table (pdbfs.studies.labfiles; the time base of the
    channel ``signal``)."""
    import pandas as pd
    if is_lab_file(path):
        return read_lab_table(path, where, signal)
    sep = _delimiter(path)
    try:
        header = 0 if _has_header(path, sep) else None
        df = pd.read_csv(path, sep=sep, engine="python", skipinitialspace=True, header=header)
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DataError(f"{where}: not a CSV table ({first})") from None
    if header is None:
        df.columns = [f"column {j + 1}" for j in range(df.shape[1])]
    return df


def _has_header(path, sep) -> bool:
    """A first line of numbers only is data, not a header."""
    with open(path, newline="", errors="replace") as fh:
        first = fh.readline().strip()
    fields = re.split(sep if sep != r"\s+" else r"\s+", first) if first else []
    try:
        [float(f) for f in fields if f.strip()]
    except ValueError:
        return True
    return not fields


def _signal_column(df, signal, where) -> int:
    """The signal's column: the second of two, or the one named ``signal``."""
    names = [split_header(c)[0] for c in df.columns]
    if signal is not None and signal in names[1:]:
        return names.index(signal, 1)
    if df.shape[1] == 2:
        return 1
    listed = ", ".join(repr(n) for n in names[1:9]) + (", ..." if len(names) > 9 else "")
    if signal is None:
        raise DataError(f"{where}: {df.shape[1] - 1} signal columns ({listed}); name the one "
                        "to use (--signal NAME)")
    raise DataError(f"{where}: no column {signal!r} among {listed}")


def _delimiter(path) -> str:
    """Comma, semicolon, tab or spaces, whichever the file's head uses."""
    import csv
    with open(path, newline="", errors="replace") as fh:
        head = fh.read(4096)
    try:
        d = csv.Sniffer().sniff(head, delimiters=",;\t ").delimiter
    except csv.Error:
        return ","
    return r"\s+" if d == " " else d


def check_trace(t, y, where: str = "trace", name: str = "") -> Trace:
    """The samples as a Trace, or DataError saying what is wrong with them."""
    t = np.asarray(t, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    if t.shape != y.shape:
        raise DataError(f"{where}: {t.size} times but {y.size} values")
    for label, v in (("time", t), ("signal", y)):
        bad = ~np.isfinite(v)
        if bad.any():
            k = int(np.argmax(bad))
            raise DataError(f"{where}: the {label} column has NaN or infinite values "
                            f"({int(bad.sum())}, first in data row {k + 1})")
    if t.size < MIN_POINTS:
        raise DataError(f"{where}: {t.size} data rows; at least {MIN_POINTS} are needed")
    steps = np.diff(t)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        raise DataError(f"{where}: time must increase strictly; data row {k + 2} has "
                        f"t = {t[k + 1]:.9g} s after t = {t[k]:.9g} s")
    return Trace(t, y, where, name)


def check_time_origin(trace: Trace, run_horizon: float) -> None:
    """A trace's times count from the rig's t = 0 (the start of a run). One
    that begins after the rig's whole run (a 20 ms record time-stamped at
    1000 s) would be simulated up to there for nothing, for minutes: refused,
    saying what to subtract."""
    t0 = float(trace.t[0])
    if t0 > run_horizon:
        raise DataError(f"{trace.source}: its times start at t = {t0:.6g} s, but they count from "
                        f"the start of the run, whose pulse lies within its first "
                        f"{run_horizon:.6g} s; give times from the trigger (subtract "
                        f"{t0:.6g} s)")


def as_trace(data, what: str = "trace", signal: str | None = None) -> Trace:
    """A Trace from a Trace, a CSV path, or a pair (t, y)."""
    if isinstance(data, Trace):
        return data
    if isinstance(data, (str, Path)):
        return read_trace(data, what, signal)
    try:
        t, y = data
    except (TypeError, ValueError):
        raise DataError(f"{what}: give a CSV path, a Trace or a pair (t, y), "
                        f"not {type(data).__name__}") from None
    return check_trace(t, y, what)


def check_horizon(t_end, trace, what="trace"):
    """Refuse a horizon that ends before the curve to match: the model is
    compared with every sample, so it is simulated to the last one at least
    (a t_end below it would be overruled without a word)."""
    if t_end is not None and t_end < float(trace.t[-1]):
        last = float(trace.t[-1])
        raise ParameterError(f"t_end = {t_end:g} s ends before the last sample of {trace.source} "
                             f"({last:g} s), which is matched sample by sample; leave t_end out, "
                             f"give at least {last:g} s, or cut the {what}")
