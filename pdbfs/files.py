"""Files written whole or not at all.

Every file pdbfs writes for a user (CSV, PNG, JSON, sweep chunks) is written
under a hidden part name beside its destination and renamed onto it only
once complete, so a failure or Ctrl-C never leaves a half-written file under
the real name. Work folders in the temporary directory (an FMU's build,
:func:`scratch_folder`) are removed when their block ends, however it ends.
Parts and work folders still there when the process is ended on purpose
(the CLI's Ctrl-C watcher, pdbfs.cli.interrupt) are removed by
:func:`discard`.

Also where pdbfs keeps files of its own: its cache folder
(:func:`cache_folder`) and the example files shipped in the package
(:func:`example_data`, pdbfs/data).
"""
from __future__ import annotations

import os
import shutil
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

_open: set[Path] = set()
_scratch: set[Path] = set()
_lock = threading.Lock()


def part_of(path) -> Path:
    """The hidden part name of ``path`` (same folder, so the rename is atomic;
    same suffix, so writers that go by it, as matplotlib, still can)."""
    path = Path(path)
    return path.with_name(f".{path.stem}.{os.getpid()}.{threading.get_ident()}.part{path.suffix}")


@contextmanager
def whole(path):
    """Yield a part path to write ``path``'s content to; on leaving the block
    the part replaces ``path``, or, if the block raised, is removed."""
    path = Path(path)
    part = part_of(path)
    with _lock:
        _open.add(part)
    try:
        yield part
        os.replace(part, path)
    finally:
        with _lock:
            _open.discard(part)
        try:
            part.unlink()
        except FileNotFoundError:
            pass


@contextmanager
def scratch_folder(prefix: str):
    """Yield a new folder in the temporary directory, named ``prefix`` and
    random letters; it is removed when the block ends, whether it ends
    normally, by an error or by Ctrl-C (a second Ctrl-C during the removal
    included: the removal is finished first), or by :func:`discard` when the
    process is ended before that."""
    folder = Path(tempfile.mkdtemp(prefix=prefix))
    with _lock:
        _scratch.add(folder)
    try:
        yield folder
    finally:
        interrupted = []
        main = threading.current_thread() is threading.main_thread()
        if main:
            import signal
            old = signal.signal(signal.SIGINT, lambda signum, frame: interrupted.append(signum))
        try:
            shutil.rmtree(folder, ignore_errors=True)
            with _lock:
                _scratch.discard(folder)
        finally:
            if main:
                signal.signal(signal.SIGINT, old)
        if interrupted:
            raise KeyboardInterrupt


def cache_folder() -> Path:
    """pdbfs's cache folder, not made here: ``$XDG_CACHE_HOME/pdbfs`` on
    Linux (default ``~/.cache/pdbfs``), the platform's user cache elsewhere."""
    import platformdirs
    return Path(platformdirs.user_cache_dir("pdbfs", appauthor=False))


def write_text(path, text: str) -> Path:
    """``path`` with ``text``, written whole."""
    with whole(path) as part:
        part.write_text(text)
    return Path(path)


def discard():
    """Remove the parts of writes still under way and the work folders of
    :func:`scratch_folder` (before a forced exit)."""
    with _lock:
        parts, folders = list(_open), list(_scratch)
    for part in parts:
        try:
            part.unlink()
        except OSError:
            pass
    for folder in folders:
        shutil.rmtree(folder, ignore_errors=True)


def save_figure(fig, path, **savefig_kw) -> Path:
    """``fig`` saved whole to ``path``, in the format its suffix names
    (matplotlib's default format when it has none)."""
    fmt = Path(path).suffix[1:]
    if not fmt:
        import matplotlib
        fmt = matplotlib.rcParams["savefig.format"]
    with whole(path) as part:
        fig.savefig(part, format=fmt, **savefig_kw)
    return Path(path)


#: the example files shipped in the package (pdbfs/data): name -> what it is
EXAMPLES = {
    "kistler_synthetic.csv": "a measured-like pressure trace of the paper rig (time_s, "
                             "pressure_Pa; 10 us sampling, noise, offset): pdbfs calibrate --trace",
    "gun_target.csv": "a target pressure pulse (time [s], pressure [Pa]): pdbfs design --target",
    "gun_firing.csv": "the chamber pressure of one firing of a large-calibre gun, synthetic "
                      "(time [s], pressure [Pa]): pdbfs fatigue --firing",
    "valve_opening.csv": "a valve command (time [ms], opening 0 to 1): pdbfs simulate --rig "
                         "hydraulic-pulse-plant --input opening=valve_opening.csv",
}


def example_data(name: str) -> Path:
    """The path of an example file shipped with pdbfs.

    Parameters
    ----------
    name : str
        One of :data:`EXAMPLES`: ``"kistler_synthetic.csv"`` (a measured-like
        pressure trace of the paper rig, for calibration),
        ``"gun_target.csv"`` (a target pulse, for design),
        ``"gun_firing.csv"`` (a synthetic chamber-pressure trace of one gun
        firing, for fatigue) or ``"valve_opening.csv"`` (a valve command, an
        input of the rig ``hydraulic-pulse-plant``).

    Returns
    -------
    pathlib.Path
        The file inside the installed package (read it, do not write it).

    Raises
    ------
    pdbfs.DataError
        For an unknown name; the message lists the names there are.

    Examples
    --------
    >>> import pdbfs
    >>> pdbfs.example_data("kistler_synthetic.csv").name
    'kistler_synthetic.csv'
    """
    from .errors import DataError
    if name not in EXAMPLES:
        raise DataError(f"no example file {name!r}; there are {', '.join(EXAMPLES)}")
    return Path(__file__).with_name("data") / name
