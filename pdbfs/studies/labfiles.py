"""Measured traces in the files data-acquisition systems write: NI TDMS
(read by npTDMS) and ASAM MDF 4 (and 3; read by asammdf), both of pdbfs's
extra ``[lab]``.

A file is read as a table like a CSV trace's: a time column (s), then its
channels, each headed ``name [unit]`` (the unit the file gives it), so that
a channel is chosen by its name as a CSV column is. The times are a TDMS
group's time channel or a channel's waveform timing (``wf_start_offset``,
``wf_increment``), or an MDF channel group's master channel; channels with
other times than the chosen one's are left out of the table, and a file
without times is refused (a trace needs them). A channel name found in two
groups is headed ``group/name``.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pdbfs.errors import DataError, MissingExtraError

#: file suffix -> (format, the module that reads it)
FORMATS = {".tdms": ("NI TDMS", "nptdms"), ".mf4": ("ASAM MDF", "asammdf"),
           ".mdf": ("ASAM MDF", "asammdf")}
#: the bytes each format's files begin with (a TDMS segment's lead-in, MDF's file identifier)
MAGIC = {"nptdms": b"TDSm", "asammdf": b"MDF     "}
#: names of a TDMS time channel (compared in lower case)
TIME_NAMES = ("time", "t", "zeit", "timestamp")


@dataclass
class Channel:
    """One channel of a lab file: its values ``y`` at times ``t`` (s; None if
    the file gives it none)."""

    name: str
    group: str
    unit: str
    y: np.ndarray
    t: np.ndarray | None


def is_lab_file(path) -> bool:
    """Whether ``path`` names a TDMS or MDF file (by its suffix)."""
    return Path(path).suffix.lower() in FORMATS


def read_lab_table(path, where: str, signal: str | None = None):
    """The table of a TDMS or MDF file: ``time [s]``, then the channels on the
    time base of ``signal`` (of the only one, without ``signal``).

    Parameters
    ----------
    path : path-like
        A ``.tdms``, ``.mf4`` or ``.mdf`` file.
    where : str
        The file as messages name it (e.g. "trace file 'run.tdms'").
    signal : str, optional
        The channel wanted (its name, or ``group/name``): its time base is read.

    Returns
    -------
    pandas.DataFrame
        The time column and the channels, headed ``name [unit]``.

    Raises
    ------
    pdbfs.errors.MissingExtraError
        Without the package that reads the format (pdbfs's extra [lab]).
    pdbfs.DataError
        For a file that is not of its format, has no channels of numbers,
        no times, or channels on several time bases and no ``signal``.
    """
    import pandas as pd
    fmt, module = FORMATS[Path(path).suffix.lower()]
    try:
        importlib.import_module(module)
    except ImportError:
        raise MissingExtraError(f"{where}: reading {fmt} files needs pdbfs's extra [lab] "
                                f"({module} is not installed): pip install 'pdbfs[lab]'") from None
    with open(path, "rb") as fh:
        head = fh.read(len(MAGIC[module]))
    if head != MAGIC[module]:
        raise DataError(f"{where}: not an {fmt} file (it does not begin as one)")
    try:
        channels = _tdms(path) if module == "nptdms" else _mdf(path)
    except (MissingExtraError, DataError):
        raise
    except Exception as err:        # the readers' own errors on a file that is not theirs
        first = str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__
        raise DataError(f"{where}: not a readable {fmt} file ({first})") from None
    if not channels:
        raise DataError(f"{where}: no channels of numbers in the file")
    base = _time_base(channels, signal, where)
    heads = _heads(channels)
    table = {"time [s]": base[0].t}
    for c in base:
        table[heads[id(c)]] = c.y
    return pd.DataFrame(table)


def _tdms(path) -> list[Channel]:
    from nptdms import TdmsFile
    out = []
    for group in TdmsFile.read(path).groups():
        chans = [c for c in group.channels() if _numbers(c[:]) or _is_time(c)]
        times = [c for c in chans if _is_time(c)]
        group_t = _seconds(times[0][:]) if times else None
        for c in chans:
            if c in times:
                continue
            y = np.asarray(c[:], dtype=float)
            if "wf_increment" in c.properties:
                t = np.asarray(c.time_track(), dtype=float)
            elif group_t is not None and group_t.size == y.size:
                t = group_t
            else:
                t = None
            out.append(Channel(c.name, group.name, str(c.properties.get("unit_string", "")), y, t))
    return out


def _is_time(c) -> bool:
    """A TDMS channel that holds times: named so, in s, or of timestamps."""
    data = c[:]
    return (c.name.strip().lower() in TIME_NAMES or c.properties.get("unit_string") == "s"
            or np.issubdtype(np.asarray(data).dtype, np.datetime64))


def _seconds(values) -> np.ndarray:
    """Times as seconds: numbers as they are, timestamps from the first."""
    v = np.asarray(values)
    if np.issubdtype(v.dtype, np.datetime64):
        return (v - v[0]) / np.timedelta64(1, "s")
    return v.astype(float)


def _numbers(values) -> bool:
    v = np.asarray(values)
    return v.ndim == 1 and v.size > 0 and (np.issubdtype(v.dtype, np.number)
                                           and not np.issubdtype(v.dtype, np.complexfloating))


def _mdf(path) -> list[Channel]:
    from asammdf import MDF
    out = []
    mdf = MDF(path)
    try:
        masters = mdf.masters_db
        for name, places in mdf.channels_db.items():
            for group, index in places:
                if masters.get(group) == index:
                    continue                   # the group's time channel
                sig = mdf.get(name, group, index)
                if not _numbers(sig.samples):
                    continue
                t = np.asarray(sig.timestamps, dtype=float) if group in masters else None
                label = mdf.groups[group].channel_group.acq_name or f"group {group}"
                out.append(Channel(name, str(label), str(sig.unit or ""),
                                   np.asarray(sig.samples, dtype=float), t))
    finally:
        mdf.close()
    return out


def _time_base(channels: list[Channel], signal, where) -> list[Channel]:
    """The channels on the time base of ``signal`` (or the only time base)."""
    timed = [c for c in channels if c.t is not None]
    if signal is not None:
        named = [c for c in channels if signal in (c.name, f"{c.group}/{c.name}")]
        if named and named[0].t is None:
            raise DataError(f"{where}: channel {signal!r} has no times (no time channel in its "
                            "group, no waveform timing); a trace needs them")
    else:
        named = []
    if not timed:
        raise DataError(f"{where}: no times: no time channel and no waveform timing "
                        f"(wf_increment) for its channels ({_listed(channels)}); a trace "
                        "needs them")
    bases: list[list[Channel]] = []
    for c in timed:
        for b in bases:
            if b[0].t.size == c.t.size and np.array_equal(b[0].t, c.t):
                b.append(c)
                break
        else:
            bases.append([c])
    if named:
        return next(b for b in bases if named[0] in b)
    if len(bases) == 1:
        return bases[0]
    shown = "; ".join(_listed(b) for b in bases)
    raise DataError(f"{where}: its channels have {len(bases)} time bases ({shown}); name the "
                    "channel to use")


def _heads(channels: list[Channel]) -> dict:
    """id(channel) -> its column header: ``name [unit]``, ``group/name`` where
    the name is in several groups."""
    count: dict[str, int] = {}
    for c in channels:
        count[c.name] = count.get(c.name, 0) + 1
    out = {}
    for c in channels:
        name = c.name if count[c.name] == 1 else f"{c.group}/{c.name}"
        out[id(c)] = f"{name} [{c.unit}]" if c.unit else name
    return out


def _listed(channels: list[Channel], most: int = 6) -> str:
    names = [c.name for c in channels]
    return ", ".join(names[:most]) + (", ..." if len(names) > most else "")
