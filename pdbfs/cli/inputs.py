"""--input NAME=FILE.csv | NAME=NUMBER: a rig's inputs from the command
line, read and checked before any work."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from pdbfs.errors import DataError, ParameterError

from .common import unique


def add_input_option(s):
    """Add ``--input NAME=FILE.csv|VALUE`` (the rig's inputs of a run) to the parser ``s``."""
    s.add_argument("--input", action="append", metavar="NAME=FILE.csv|NAME=VALUE",
                   help="an input of the rig (`pdbfs params` lists them): a CSV file of time "
                   "and value columns (a header may give units, e.g. time [ms]; a time given "
                   "twice is a jump), interpolated linearly and covering the run, or a number "
                   "held throughout (repeatable; an input not given holds its start value)")


def parse_inputs(items, dae) -> dict | None:
    """{input name: (t, u) or number} from --input items, or None."""
    if not items:
        return None
    pairs = []
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name or not value.strip():
            raise ParameterError(f"--input {item!r}: expected NAME=FILE.csv or NAME=VALUE, e.g. "
                                 "command=command.csv")
        if name not in dae.input_names:
            have = ", ".join(dae.input_names) or "none"
            raise ParameterError(f"--input {item!r}: {name!r} is not an input of rig {dae.name} "
                                 f"(its inputs: {have})")
        pairs.append((name, value.strip()))
    out = {}
    for name, value in unique(pairs, "--input").items():     # a name twice: refused first
        try:
            out[name] = float(value)
        except ValueError:
            unit = next(u.unit for u in dae.inputs if u.name == name)
            out[name] = read_input(value, name, unit)
    return out


def read_input(path, name, unit):
    """(t, u) of a CSV file: time in the first column (s, or as its header
    says), the input's values in the second (or in the column named like
    the input), converted to SI by the header's units."""
    import pandas as pd        # (here: a run without --input imports neither)

    from pdbfs.studies.fitting.traces import read_table, split_header, to_si
    where = f"--input {name}: file {str(path)!r}"
    p = Path(path)
    if not p.is_file():
        raise DataError(f"{where}: no such file")
    df = read_table(p, where, name)
    names = [split_header(c)[0] for c in df.columns]
    if df.shape[1] < 2 or len(df) == 0:
        raise DataError(f"{where}: needs a time column and a value column, and rows of data")
    j = names.index(name, 1) if name in names[1:] else 1 if df.shape[1] == 2 else None
    if j is None:
        raise DataError(f"{where}: {df.shape[1] - 1} value columns; name one {name!r}")
    cols = []
    for k in (0, j):
        col = pd.to_numeric(df.iloc[:, k], errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(~np.isfinite(col))
        if bad.size:
            raise DataError(f"{where}: column {df.columns[k]!r}, data row {bad[0] + 1}: "
                            f"{df.iloc[bad[0], k]!r} is not a finite number")
        cols.append(col)
    t_factor, t_si = to_si(split_header(df.columns[0])[1], where, df.columns[0])
    if t_si not in ("", "s"):
        raise DataError(f"{where}: the first column {df.columns[0]!r} must be time (s, ms, us)")
    u_unit = split_header(df.columns[j])[1]
    u_factor, u_si = to_si(u_unit, where, df.columns[j])
    if u_si and u_si != unit:
        raise DataError(f"{where}: column {df.columns[j]!r} is in {u_unit}, but input {name} is "
                        f"in {unit}")
    return cols[0] * t_factor, cols[1] * u_factor
