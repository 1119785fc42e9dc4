"""A compiled run kept in the library's memory (``CompiledODE.run_summary``
with ``keep``): a summary alone needs no states on the grid, so they are made
from the run's record only when first read, at any size of the record. The
records a library keeps for runs whose states were never read are bounded
(KEPT_BYTES): past it, the oldest are made into their states and freed."""
from __future__ import annotations

import ctypes
import threading
import weakref
from collections import deque

import numpy as np

#: room for the trajectory driver's message (native/c/library/pdbfs_run_trajectory.c)
MSG_LEN = 1024
#: bytes of records one library keeps for runs whose states were not read: past
#: it the oldest runs' states are made (a few grids of numbers) and their records freed
KEPT_BYTES = 256e6


class KeptRuns:
    """The runs a library keeps (weak references, oldest first) and about
    the bytes of their records: a running total, made exact again (the runs
    gone or made taken out) whenever it passes KEPT_BYTES."""

    def __init__(self):
        self.runs = deque()
        self.nbytes = 0.0
        self._lock = threading.Lock()

    def bound(self) -> None:
        """The runs kept within KEPT_BYTES: the oldest made into their states."""
        with self._lock:
            live = [r for r in (w() for w in self.runs) if r is not None and r._made is None]
            total = sum(r.nbytes for r in live)
            old = []
            while total > KEPT_BYTES and len(live) > 1:
                run = live.pop(0)
                total -= run.nbytes
                old.append(run)
            self.runs = deque(weakref.ref(r) for r in live)
            self.nbytes = total
        for run in old:                 # made outside the lock (each run has its own)
            run.states()


class KeptRun:
    """A run of ``run_summary(keep=True)`` kept in the library's memory
    (its record of every step) until its states on the grid are made:
    ``states()`` makes them on its first call (each step's dense output at
    the grid's times in it, native/c/library/pdbfs_run_trajectory.c: the numbers of a run
    that wrote them as it went), frees the record and answers the same
    after; garbage collection frees it too."""

    def __init__(self, lib, handle: int, t: np.ndarray, steps: int):
        self._lib, self._handle, self._t = lib, handle, t
        self._made = None
        self._lock = threading.Lock()
        #: the record's size, about: per step its stages, state, roles and their rates
        self.nbytes = 8 * (steps + 1) * (17 * (lib.nx + 1) + 2 * len(lib.roles) + 4)
        kept = lib.kept                 # (no call: a run's Python is counted)
        kept.runs.append(weakref.ref(self))
        kept.nbytes += self.nbytes
        if kept.nbytes > KEPT_BYTES:
            kept.bound()

    def states(self) -> tuple[np.ndarray | None, int, str]:
        """(X (nx x len(t)), 0) or (None, the driver's code, its message)."""
        with self._lock:             # two threads reading one Result: made once, freed once
            if self._made is not None:
                return self._made
            t = self._t
            X = np.empty((self._lib.nx, t.size))
            msg = ctypes.create_string_buffer(MSG_LEN)
            code = self._lib._trajectory(self._handle, t.size, t.ctypes.data, X.ctypes.data, msg,
                                         MSG_LEN)
            self._lib._release(self._handle)
            self._made = (None, int(code), msg.value.decode(errors="replace").strip()) if code \
                else (X, 0, "")
            return self._made

    def __del__(self):             # never read: the record freed with its Result
        if self._made is None:
            self._lib._release(self._handle)
