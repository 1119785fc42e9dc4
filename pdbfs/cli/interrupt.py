"""Ctrl-C for every command: one line, exit status 130, promptly.

Python runs its SIGINT handler only between bytecodes; inside a CasADi call
(an integration of many seconds, with the GIL released) it runs late or, when
CasADi polls for signals itself, its KeyboardInterrupt is swallowed and the
run goes on to exit 0. So the signal is also watched at C level: Python's
own handler writes each signal's number to a socket pair (signal.set_wakeup_fd;
a socket, not a pipe, as Windows requires) the moment it arrives, and a thread
reading the other end gives the main thread
GRACE seconds to stop by itself (a KeyboardInterrupt leaving the watched
block); otherwise it prints the line and ends the process. After the block
the previous handler is back (cli.main may run many times in one process).

Code that defers Ctrl-C on purpose (a sweep finishing and saving the chunk at
hand) installs a handler of its own; while it is installed the watcher leaves
the interrupt to it.
"""
from __future__ import annotations

import os
import signal
import socket
import sys
import threading
from contextlib import contextmanager

from pdbfs import files

#: seconds the main thread has to stop by itself before the process is ended
GRACE = 1.0
STATUS = 130                     # 128 + SIGINT, as a shell reports it

_done = threading.Event()


def _handler(signum, frame):
    # CasADi polls for signals inside its solvers, prints the KeyboardInterrupt
    # and carries on: there the watcher ends the process instead
    if frame is not None and f"{os.sep}casadi{os.sep}" in frame.f_code.co_filename:
        return
    # at the entry of a compiled run's memory probe (a ctypes callback) a raise would be
    # printed as ignored and the run would go on: kept, raised when the call returns
    # (not imported: no compiled run yet; a command's --help or bad option stays quick)
    memory = sys.modules.get("pdbfs.simulation.setup.memory")
    if memory is not None and memory.kept_at_probe(frame):
        return
    raise KeyboardInterrupt


def done():
    """The main thread has handled the interrupt (and prints its own line)."""
    _done.set()


@contextmanager
def watching():
    """SIGINT watched while the block runs (main thread only; elsewhere, or
    where that cannot be set up, Python's own handling stays); afterwards
    the previous handler and wakeup fd are back and the watcher ends."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    try:
        r, w = socket.socketpair()
    except OSError:
        yield
        return
    w.setblocking(False)
    _done.clear()
    old_handler = signal.signal(signal.SIGINT, _handler)
    try:
        old_fd = signal.set_wakeup_fd(w.fileno(), warn_on_full_buffer=False)
    except ValueError:
        signal.signal(signal.SIGINT, old_handler)
        r.close()
        w.close()
        yield
        return
    watcher = threading.Thread(target=_watch, args=(r,), name="pdbfs-ctrl-c", daemon=True)
    watcher.start()
    try:
        yield
    except KeyboardInterrupt:
        _done.set()                  # stopped by itself: the caller says so
        raise
    finally:
        signal.set_wakeup_fd(old_fd)
        signal.signal(signal.SIGINT, old_handler)
        w.close()                    # the watcher reads the end of its socket and stops
        watcher.join(1.0)


def _watch(sock):
    try:
        while True:
            try:
                data = sock.recv(64)
            except OSError:
                return
            if not data:
                return
            if signal.SIGINT not in data or signal.getsignal(signal.SIGINT) is not _handler:
                continue             # another signal, or someone defers Ctrl-C on purpose
            if _done.wait(GRACE):
                return
            try:
                files.discard()          # no half-written file left under a part name
                sys.stderr.write("pdbfs: interrupted\n")
                sys.stderr.flush()
            finally:
                os._exit(STATUS)
    finally:
        sock.close()
