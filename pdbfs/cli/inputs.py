"""--input NAME=FILE.csv | NAME=NUMBER: a rig's inputs from the command
line, read and checked before any work."""
from __future__ import annotations

from pathlib import Path

from pdbfs.errors import DataError, ParameterError

from .common import unique
from .progress import Progress


def add_input_option(s):
    """Add ``--input NAME=FILE.csv|VALUE`` (the rig's inputs of a run) to the parser ``s``."""
    s.add_argument("--input", action="append", metavar="NAME=FILE.csv|NAME=VALUE",
                   help="an input of the rig (`pdbfs params` lists them): a CSV file (.gz, "
                   ".bz2, .xz, .zip too; # starts a comment line) of a time column, named time "
                   "or t in a header (the first without one), and a value column (named like "
                   "the input where there are several); a header may give units, e.g. "
                   "time [ms]; a time given twice is a jump; interpolated linearly and covering "
                   "the run; or a number held throughout (repeatable; an input not given holds "
                   "its start value)")


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
    """(t, u) of a CSV file (read_table's: delimiter sniffed, ``#`` comments
    skipped, compressed files read): the time column named ``time`` or
    ``t`` in a header (the first column without one), in s or as its header
    says; the input's values in the only other column, or the one named
    like the input; converted to SI by the header's units, which must be the
    input's."""
    from pdbfs.studies.fitting.traces import read_table, split_header, table_columns
    where = f"--input {name}: file {str(path)!r}"
    p = Path(path)
    if not p.is_file():
        raise DataError(f"{where}: no such file")
    with Progress(f"reading {path}", "rows") as progress:     # a long file: said as it goes
        df = read_table(p, where, progress, name)
    t, u, _, j, u_si = table_columns(df, where, name if _named(df, name) else None,
                                     f"name one {name!r}", "value")
    if u_si and u_si != unit:
        given = split_header(df.columns[j])[1]
        raise DataError(f"{where}: column {df.columns[j]!r} is in {given}, but input {name} is "
                        f"in {unit}")
    return t, u


def _named(df, name) -> bool:
    from pdbfs.studies.fitting.traces import split_header
    return any(split_header(c)[0] == name for c in df.columns)
