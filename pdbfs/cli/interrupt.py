"""Ctrl-C for every command: one line, exit status 130, promptly.

Python runs its SIGINT handler only between bytecodes; inside a CasADi call
(an integration of many seconds, with the GIL released) it runs late or, when
CasADi polls for signals itself, its KeyboardInterrupt is swallowed and the
run goes on to exit 0. So the signal is also watched at C level: Python's
own handler writes each signal's number to a pipe (signal.set_wakeup_fd) the
moment it arrives, and a thread reading that pipe gives the main thread
GRACE seconds to stop by itself (cli.main catches the KeyboardInterrupt and
calls done()); otherwise it prints the line and ends the process.

Code that defers Ctrl-C on purpose (a sweep finishing and saving the chunk at
hand) installs a handler of its own; while it is installed the watcher leaves
the interrupt to it.
"""
from __future__ import annotations

import os
import signal
import sys
import threading

#: seconds the main thread has to stop by itself before the process is ended
GRACE = 1.0
STATUS = 130                     # 128 + SIGINT, as a shell reports it

_done = threading.Event()


def _handler(signum, frame):
    # CasADi polls for signals inside its solvers, prints the KeyboardInterrupt
    # and carries on: there the watcher ends the process instead
    if frame is not None and f"{os.sep}casadi{os.sep}" in frame.f_code.co_filename:
        return
    raise KeyboardInterrupt


def done():
    """The main thread has handled the interrupt (and prints its own line)."""
    _done.set()


def install() -> bool:
    """Watch SIGINT (main thread only; False where that is not possible)."""
    if threading.current_thread() is not threading.main_thread():
        return False
    try:
        r, w = os.pipe()
        os.set_blocking(w, False)
        signal.signal(signal.SIGINT, _handler)
        signal.set_wakeup_fd(w, warn_on_full_buffer=False)
    except (OSError, ValueError):
        return False
    threading.Thread(target=_watch, args=(r,), name="pdbfs-ctrl-c", daemon=True).start()
    return True


def _watch(fd):
    while True:
        try:
            data = os.read(fd, 64)
        except OSError:
            return
        if not data:
            return
        if signal.SIGINT not in data or signal.getsignal(signal.SIGINT) is not _handler:
            continue             # another signal, or someone defers Ctrl-C on purpose
        if _done.wait(GRACE):
            return
        try:
            sys.stderr.write("pdbfs: interrupted\n")
            sys.stderr.flush()
        finally:
            os._exit(STATUS)
