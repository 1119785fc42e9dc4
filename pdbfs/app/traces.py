"""Uploaded traces, kept on the server: the page holds only a key, a name and
a few numbers, so a trace does not travel with every edit. A trace is read
as ``pdbfs calibrate --trace`` reads a file, refused above ``MAX_UPLOAD``
bytes, stored as .npy files under the app's cache folder (the folder is
named by an environment variable, so the processes of background jobs find
it too) and drawn decimated to at most ``MAX_DRAWN`` points."""
from __future__ import annotations

import atexit
import base64
import inspect
import os
import re
import shutil
import tempfile
import uuid
from pathlib import Path

import numpy as np

from pdbfs.errors import DataError, PdbfsError

#: largest trace file accepted, in bytes (a million samples of text is about 40 MB)
MAX_UPLOAD = 20_000_000
#: most points of a trace the page draws (its peaks are kept: min and max per bin)
MAX_DRAWN = 4000
ENV = "PDBFS_APP_TRACES"
_KEY = re.compile(r"^[0-9a-f]{32}$")
_SUFFIX = re.compile(r"^\.[A-Za-z0-9]{1,8}$")


def shown_name(filename) -> str:
    """The uploaded file's name as the page may print it (control characters
    escaped, at most 80 characters)."""
    text = repr(str(filename or ""))[1:-1]
    return text if len(text) <= 80 else text[:60] + "..." + text[-17:]


def check_name(filename) -> str:
    """The uploaded file's name, or a DataError if it is no plain file name
    (empty, a folder, a path, a NUL byte, longer than 255 bytes)."""
    name = str(filename or "")
    why = None
    if not name.strip():
        why = "is empty"
    elif "\x00" in name:
        why = "holds a NUL byte"
    elif len(name.encode("utf-8", "surrogatepass")) > 255:
        why = f"is {len(name.encode('utf-8', 'surrogatepass'))} bytes long (at most 255)"
    elif name in (".", "..") or "/" in name or "\\" in name:
        why = "is not a plain file name"
    if why:
        raise DataError(f"trace file {shown_name(name)!r}: the file name {why}; rename the file")
    return name


def check_size(filename, contents: str):
    """A DataError if the upload (a base64 data URL) holds more than MAX_UPLOAD bytes."""
    n = len(contents or "") - len((contents or "").partition(",")[0]) - 1
    size = max(n, 0) * 3 // 4
    if size > MAX_UPLOAD:
        raise DataError(f"trace file {shown_name(filename)!r}: {size / 1e6:.1f} MB, more than the "
                        f"page takes ({MAX_UPLOAD / 1e6:.0f} MB); thin it out, or use "
                        "pdbfs calibrate --trace on the command line")


def read_upload(filename, contents: str, signal=None):
    """A trace uploaded by the browser (a data URL) read as ``pdbfs calibrate
    --trace`` reads a file; errors name the file as uploaded."""
    from pdbfs.studies import read_trace
    name = check_name(filename)
    check_size(name, contents)
    try:
        data = base64.b64decode((contents or "").partition(",")[2], validate=False)
    except (ValueError, TypeError):
        raise DataError(f"trace file {shown_name(name)!r}: the upload could not be decoded") from None
    suffix = Path(name).suffix if _SUFFIX.match(Path(name).suffix or "") else ".csv"
    with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp:
        path = Path(tmp) / ("upload" + suffix)     # never a path the client chose
        path.write_bytes(data)
        kwargs = {}
        if signal and "signal" in inspect.signature(read_trace).parameters:
            kwargs["signal"] = signal
        try:
            return read_trace(path, **kwargs)
        except PdbfsError as err:
            raise type(err)(str(err).replace(str(path), shown_name(name))) from None


def folder() -> Path:
    """Where traces are kept: the app's (create_app sets the variable), else a
    temporary folder of this process, removed when it ends."""
    if not os.environ.get(ENV):
        path = tempfile.mkdtemp(prefix="pdbfs-app-traces-")
        atexit.register(shutil.rmtree, path, True)
        os.environ[ENV] = path
    p = Path(os.environ[ENV])
    p.mkdir(parents=True, exist_ok=True)
    return p


def store(name: str, t, y) -> dict:
    """Keep a trace on the server; what the page holds of it."""
    key = uuid.uuid4().hex
    np.save(folder() / f"{key}.npy", np.vstack([np.asarray(t, float), np.asarray(y, float)]))
    t = np.asarray(t, float)
    return {"key": key, "name": shown_name(name), "n": int(t.size),
            "t0": float(t[0]), "t1": float(t[-1])}


def load(info) -> tuple:
    """The (t, y) of a kept trace, from what the page holds; DataError if gone."""
    key = str((info or {}).get("key", ""))
    if not _KEY.match(key):
        raise DataError("the uploaded trace is not known to the server; upload it again")
    try:
        ty = np.load(folder() / f"{key}.npy")
    except OSError:
        raise DataError(f"trace file {info.get('name', '')!r} is no longer on the server "
                        "(was it restarted?); upload it again") from None
    return ty[0], ty[1]


def decimate(t, y, n: int = MAX_DRAWN):
    """At most about ``n`` points of (t, y) for drawing: each bin's first,
    minimum and maximum, so no peak is lost (NaN counts as neither)."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    if t.size <= n:
        return t, y
    width = -(-t.size // max(n // 3, 1))          # samples per bin, rounded up
    bins = -(-t.size // width)
    pad = bins * width - t.size
    grid = np.concatenate([y, np.full(pad, np.nan)]).reshape(bins, width)
    lo_fill = np.where(np.isnan(grid), np.inf, grid)
    hi_fill = np.where(np.isnan(grid), -np.inf, grid)
    start = np.arange(bins) * width
    idx = np.concatenate([start, start + lo_fill.argmin(axis=1), start + hi_fill.argmax(axis=1),
                          [t.size - 1]])
    idx = np.unique(np.minimum(idx, t.size - 1))
    return t[idx], y[idx]
