"""Measured traces and target curves: a time column (s) and a signal column
(SI units, Pa for a pressure), read from a CSV file with a header, checked
before anything is fitted to them."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdbfs.errors import DataError

#: fewer samples than this cannot carry a pulse, whatever is fitted
MIN_POINTS = 10


@dataclass(frozen=True)
class Trace:
    """Samples ``y`` (in the signal's SI unit) at strictly increasing times ``t`` (s)."""

    t: np.ndarray
    y: np.ndarray
    source: str = "trace"
    name: str = ""          # the signal column's header, if read from a file

    def __len__(self):
        return len(self.t)

    @property
    def span(self) -> float:
        return float(self.t[-1] - self.t[0])


def read_trace(path, what: str = "trace") -> Trace:
    """Read a CSV trace: a header line, then rows of time (s) and signal; the
    delimiter is sniffed (comma, semicolon, tab or spaces). Extra columns
    are ignored. DataError, naming the file, for anything else."""
    import pandas as pd
    p = Path(path)
    where = f"{what} file {str(path)!r}"
    if not p.is_file():
        raise DataError(f"{where}: no such file")
    if p.stat().st_size == 0:
        raise DataError(f"{where}: the file is empty")
    try:
        df = pd.read_csv(p, sep=_delimiter(p), engine="python", skipinitialspace=True)
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DataError(f"{where}: not a CSV table ({first})") from None
    if df.shape[1] < 2:
        raise DataError(f"{where}: needs two columns, time (s) and the signal; found "
                        f"{df.shape[1]} ({', '.join(map(str, df.columns)) or 'none'})")
    if len(df) == 0:
        raise DataError(f"{where}: a header but no data rows")
    cols = []
    for j in (0, 1):
        col = pd.to_numeric(df.iloc[:, j], errors="coerce")
        bad = col.isna() & df.iloc[:, j].notna() & (df.iloc[:, j].astype(str).str.strip() != "")
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise DataError(f"{where}: column {df.columns[j]!r}, data row {row + 1}: "
                            f"{df.iloc[row, j]!r} is not a number")
        cols.append(col.to_numpy(dtype=float))
    return check_trace(cols[0], cols[1], f"{where}", name=str(df.columns[1]))


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


def as_trace(data, what: str = "trace") -> Trace:
    """A Trace from a Trace, a CSV path, or a pair (t, y)."""
    if isinstance(data, Trace):
        return data
    if isinstance(data, (str, Path)):
        return read_trace(data, what)
    try:
        t, y = data
    except (TypeError, ValueError):
        raise DataError(f"{what}: give a CSV path, a Trace or a pair (t, y), "
                        f"not {type(data).__name__}") from None
    return check_trace(t, y, what)
