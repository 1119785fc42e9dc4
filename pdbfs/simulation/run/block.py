"""One thread's buffer for the compiled library's small arguments and answers
(``CompiledODE._block``): made once, with the addresses C reads and writes,
because an address costs a microsecond or two and a run of the paper rig
costs 150."""
from __future__ import annotations

import struct

import numpy as np


class Block:
    """p, x0, info[n_info], the summary values[n_sum], the summary's code (one
    double's room), its two messages (msg_len and note_len bytes) and the
    kept run's handle, in one float64 buffer ``buf``; and ``c`` for
    pdbfs_batch_start's conditions or the three modes. C writes every answer
    before it returns.

    ``addr``: the addresses of (p, x0, info, msg, values, code, note, handle),
    in run_summary's order. ``unpack(bytes)``: (info..., values..., code, the
    note's first byte, handle) in one call (a Python call more is a
    microsecond or two after other work)."""

    def __init__(self, n_p: int, nx: int, nc: int, n_info: int, n_sum: int, msg_len: int,
                 note_len: int):
        self.c = np.zeros(max(nc, 3))
        self.c_addr = self.c.ctypes.data
        n_in = n_p + nx
        n = n_in + n_info + n_sum + 1 + (msg_len + note_len + 7) // 8 + 1
        self.buf = buf = np.zeros(n)
        self.p, self.x0 = buf[:n_p], buf[n_p:n_in]
        self.info, self.out = buf[n_in:n_in + n_info], buf[n_in + n_info:n_in + n_info + n_sum]
        base = buf.ctypes.data
        code_at = 8 * (n_in + n_info + n_sum)           # bytes from base: the code, then the messages
        note_at = code_at + 8 + msg_len
        self.addr = (base, base + 8 * n_p, base + 8 * n_in, base + code_at + 8,
                     base + 8 * (n_in + n_info), base + code_at, base + note_at, base + 8 * (n - 1))
        raw = buf.view(np.uint8)
        self.code = raw[code_at:code_at + 4].view(np.intc)
        self.msg, self.note = raw[code_at + 8:note_at], raw[note_at:note_at + note_len]
        self.handle = buf[-1:].view(np.uint64)
        layout = struct.Struct(f"={8 * n_in}x{n_info}d{n_sum}di{4 + msg_len}xB"
                               f"{8 * (n - 1) - note_at - 1}xQ")
        assert layout.size == buf.nbytes
        self.unpack = layout.unpack_from
        #: the buffer's bytes for ``unpack`` (a memoryview asks numpy nothing: after other
        #: work, numpy's first call costs 10-20 us on this project's machine)
        self.bytes = memoryview(buf).cast("B")
