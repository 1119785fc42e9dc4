"""Measured traces and target curves: a time column and a signal column,
read from a CSV file (units in the header converted to SI, the column chosen
by name), checked before anything is fitted to them."""
from __future__ import annotations

import io
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
    """A measured signal: samples ``y`` (in the signal's SI unit) at strictly
    increasing times ``t`` (s), as ``read_trace`` makes it; ``calibrate``
    and ``design`` take one (or ``(t, y)`` arrays) as their trace or target.

    Parameters
    ----------
    t : numpy.ndarray
        The sample times, s, strictly increasing.
    y : numpy.ndarray
        The samples, in the signal's SI unit.
    source : str
        Where it came from, as messages name it (a file).
    name : str
        The signal column's name (its unit stripped), if read from a file.
    unit : str
        The signal's SI unit, if the file's header gave one.
    time_unit : str
        The unit the file's header gave the time in ("" if none).
    """

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
    """Read a measured trace from a CSV file of a time column and a signal
    column (delimiter sniffed, ``#`` comment lines skipped, .gz, .bz2, .xz
    and .zip read as they are).

    With a header, the time column is the one named ``time`` or ``t``
    (``time [ms]``, ``time_s``), wherever it stands; without one, the
    first. Units in the header (``time [ms]``, ``oil.pressure [kPa]``) are
    converted to SI; an unknown unit is refused. The results CSV of
    ``pdbfs simulate`` (header ``name [unit]``) is a trace.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file.
    what : str
        What the file is, as messages name it ("trace", "target").
    signal : str, optional
        The column to use where there is more than one besides the time.

    Returns
    -------
    Trace
        The samples, SI units.

    Raises
    ------
    pdbfs.DataError
        Naming the file: missing, empty, unreadable, an unknown unit, times
        that do not increase, values that are not finite numbers, or more
        than one signal column and no ``signal``.

    Examples
    --------
    >>> import pdbfs
    >>> from pdbfs.studies import read_trace
    >>> tr = read_trace(pdbfs.example_data("kistler_synthetic.csv"))
    >>> len(tr), tr.name, f"{tr.span * 1e3:.3g} ms"
    (2150, 'pressure_Pa', '21.5 ms')
    """
    p = Path(path)
    where = f"{what} file {str(path)!r}"
    if not p.is_file():
        raise DataError(f"{where}: no such file")
    if p.stat().st_size == 0:
        raise DataError(f"{where}: the file is empty")
    df = read_table(p, where, signal=signal)
    t, y, t_unit, j, y_si = table_columns(df, where, signal, "--signal NAME")
    y_name = split_header(df.columns[j])[0]
    trace = check_trace(t, y, where, name=y_name)
    return Trace(trace.t, trace.y, where, y_name, y_si, t_unit or "")


def _shown(text) -> str:
    """A header as a message shows it: characters that do not print (a binary
    file's) escaped, as Python writes them, so that a terminal and a page agree."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


#: a time column's name, its unit in the name's end where the header gives none (time_ms)
_TIME_NAME = re.compile(r"^(?:t|time)(?:[ _](?P<unit>s|ms|us|µs|μs))?$", re.IGNORECASE)


def table_columns(df, where: str, signal: str | None, option: str, kind: str = "signal"):
    """(t in s, values in SI, the time's unit as the header gave it or None,
    the value column's index, its SI unit or "") of a table read by
    read_table: the time column by its name (time_column), the ``kind``
    column the only other one or the one named ``signal`` (a DataError
    naming ``option`` where there are several); a cell that is no number
    is refused, shown as the file has it (NaN and inf are left to the
    trace's checks)."""
    import pandas as pd
    if df.shape[1] < 2:
        raise DataError(f"{where}: needs two columns, time (s) and the {kind}; found "
                        f"{df.shape[1]} ({', '.join(map(_shown, df.columns)) or 'none'})")
    if len(df) == 0:
        raise DataError(f"{where}: a header but no data rows")
    i, t_unit = time_column(df, where)
    names = [split_header(c)[0] for c in df.columns]
    rest = [k for k in range(df.shape[1]) if k != i]
    named = [k for k in rest if signal is not None and names[k] == signal]
    if named:
        j = named[0]
    elif len(rest) == 1:           # the one signal, whatever its name
        j = rest[0]
    else:
        listed = ", ".join(repr(names[k]) for k in rest[:8]) + (", ..." if len(rest) > 8 else "")
        raise DataError(f"{where}: {len(rest)} {kind} columns ({listed}); name the one to use "
                        f"({option})" if signal is None else
                        f"{where}: no column {signal!r} among {listed}")
    cols = []
    for k in (i, j):
        raw = df.iloc[:, k]
        col = pd.to_numeric(raw, errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(np.isnan(col) & ~_nan_text(raw))
        if bad.size:
            cell = "" if pd.isna(raw.iloc[bad[0]]) else str(raw.iloc[bad[0]]).strip()
            shown = f"{cell} is not a number" if cell else "an empty cell"
            raise DataError(f"{where}: column {names[k]}, data row {bad[0] + 1}: {shown}")
        cols.append(col)
    t_factor, _ = to_si(t_unit, where, df.columns[i])
    y_unit = split_header(df.columns[j])[1]
    y_factor, y_si = to_si(y_unit, where, df.columns[j])
    return cols[0] * t_factor, cols[1] * y_factor, t_unit, j, y_si


def _nan_text(raw) -> np.ndarray:
    """Where a column's cell says NaN itself (a number, not a typing error)."""
    if raw.dtype.kind == "f":
        return np.ones(len(raw), bool)         # parsed as numbers: an empty cell is NaN there
    text = raw.astype(str).str.strip().str.lower()
    return text.isin(["nan", "-nan", "+nan"]).to_numpy()


def time_column(df, where: str) -> tuple[int, str | None]:
    """(index, unit as given or None) of a table's time column: the one
    whose name is ``time`` or ``t`` (``time [ms]``, ``time_ms``); without a
    header, the first. A header without one is refused (its first column
    may be anything: a force read as time would be a wrong trace), as is a
    time column in another unit than a time's."""
    if df.attrs.get("headerless", False):
        i, unit = 0, None
    else:
        found = []
        for k, c in enumerate(df.columns):
            name, unit = split_header(c)
            m = _TIME_NAME.match(name.strip())
            if m:
                found.append((k, unit if unit is not None else m.group("unit")))
        if len(found) != 1:
            listed = ", ".join(repr(str(c)) for c in df.columns[:8])
            raise DataError(f"{where}: {'no' if not found else 'more than one'} time column "
                            f"among {listed}; name one 'time' (with its unit: 'time [ms]')")
        i, unit = found[0]
    if unit is not None and UNITS.get(unit, (0, ""))[1] != "s":
        raise DataError(f"{where}: the column {str(df.columns[i])!r} must be time; its unit "
                        f"{unit!r} is not one of time (s, ms, us)")
    return i, unit


#: rows a long table is read in at a time, when its reading is shown (read_table's progress)
CHUNK_ROWS = 1_000_000


def read_table(path: Path, where: str, progress=None, signal: str | None = None):
    """The CSV table of ``path`` as a DataFrame: its delimiter sniffed
    (comma, semicolon, tab or spaces), lines starting with ``#`` skipped,
    a compressed file (.gz, .bz2, .xz, .zip) read as it is; its header
    optional (without one the columns are "column 1", ... and
    ``df.attrs["headerless"]`` is True); a file that is no table is a DataError naming
    ``where``. ``progress`` (a callable of the rows read so far), where
    given, is called as a long file is read (CHUNK_ROWS at a time). A TDMS
    or MDF file is read as the same table (pdbfs.studies.labfiles: its time
    base of the channel ``signal``)."""
    import pandas as pd
    if is_lab_file(path):
        return read_lab_table(path, where, signal)
    head = _head_lines(path, where)
    if not head:
        raise DataError(f"{where}: no table in it (only comment or empty lines)")
    sep = _delimiter("\n".join(head))
    header = 0 if _has_header(head[0], sep) else None
    try:
        args = dict(sep=sep, engine="c", skipinitialspace=True, header=header, comment="#",
                    skip_blank_lines=True, compression="infer")
        if progress is None:
            df = pd.read_csv(path, **args)
        else:
            parts, rows = [], 0
            with pd.read_csv(path, chunksize=CHUNK_ROWS, **args) as reader:
                for part in reader:
                    parts.append(part)
                    rows += len(part)
                    progress(rows)
            df = pd.concat(parts, ignore_index=True) if len(parts) > 1 else parts[0]
            del parts
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError, OSError, EOFError) as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DataError(f"{where}: not a CSV table ({first})") from None
    if header is None:
        df.columns = [f"column {j + 1}" for j in range(df.shape[1])]
    df.attrs["headerless"] = header is None
    return df


def _head_lines(path, where, n: int = 50) -> list[str]:
    """The first ``n`` lines of the file that are neither empty nor
    comments, decompressed where its name says (.gz, .bz2, .xz, .zip)."""
    import bz2
    import gzip
    import lzma
    import zipfile
    suffix = Path(path).suffix.lower()
    try:
        if suffix == ".zip":
            with zipfile.ZipFile(path) as z:
                names = z.namelist()
                if len(names) != 1:
                    raise DataError(f"{where}: a zip file of {len(names)} files; give one CSV")
                fh = io.TextIOWrapper(z.open(names[0]), errors="replace", newline="")
                return _first_lines(fh, n)
        opener = {".gz": gzip.open, ".bz2": bz2.open, ".xz": lzma.open}.get(suffix, open)
        with opener(path, "rt", errors="replace", newline="") as fh:
            return _first_lines(fh, n)
    except (OSError, EOFError, zipfile.BadZipFile, lzma.LZMAError) as err:
        raise DataError(f"{where}: cannot be read as a {suffix or 'text'} file ({err})") from None


def _first_lines(fh, n) -> list[str]:
    out = []
    for line in fh:
        text = line.strip()
        if text and not text.startswith("#"):
            out.append(text)
            if len(out) == n:
                break
    return out


def _has_header(first: str, sep) -> bool:
    """A first line of numbers only is data, not a header."""
    fields = re.split(sep if sep != r"\s+" else r"\s+", first) if first else []
    try:
        [float(f.strip().strip('"')) for f in fields if f.strip()]
    except ValueError:
        return True
    return not fields


def _delimiter(head: str) -> str:
    """Comma, semicolon, tab or spaces, whichever the file's head uses."""
    import csv
    try:
        d = csv.Sniffer().sniff(head[:4096], delimiters=",;\t ").delimiter
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
