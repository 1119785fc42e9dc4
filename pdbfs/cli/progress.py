"""Progress of a long step of a command, on stderr: nothing for work that
ends within AFTER seconds; then what is done so far, rewritten in place on a
terminal (and cleared at the end), or a line every EVERY seconds elsewhere
(a log, a pipe), so that no command works for minutes without a word."""
from __future__ import annotations

import sys
import time

#: seconds of work before the first word
AFTER = 2.0
#: seconds between two lines where stderr is no terminal (on one, 0.5 s)
EVERY = 10.0


class Progress:
    """A callable ``progress(done, total=None)`` for ``label`` ("writing
    results.csv", "calibrating"); ``unit`` names what is counted. Use it as a
    context manager: leaving the block clears the terminal's line."""

    def __init__(self, label: str, unit: str = "", stream=None, clock=time.monotonic):
        self.label, self.unit = label, unit
        self.stream = stream if stream is not None else sys.stderr
        self.clock = clock
        self.t0 = clock()
        self.last = None
        try:
            self.tty = self.stream.isatty()
        except (AttributeError, ValueError):
            self.tty = False

    def __call__(self, done, total=None):
        now = self.clock()
        elapsed = now - self.t0
        if elapsed < AFTER or (self.last is not None
                               and now - self.last < (0.5 if self.tty else EVERY)):
            return
        self.last = now
        unit = f" {self.unit}" if self.unit else ""
        if total:
            text = f"{done} of {total}{unit} ({100.0 * done / total:.0f} %)"
            if 0 < done < total:
                text += f", about {_duration(elapsed * (total - done) / done)} to go"
        else:
            text = f"{done}{unit}"
        text = f"pdbfs: {self.label}: {text}, {_duration(elapsed)} so far"
        self.stream.write(f"\r{text}\033[K" if self.tty else text + "\n")
        self.stream.flush()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.tty and self.last is not None:
            self.stream.write("\r\033[K")
            self.stream.flush()
        return False


def _duration(s: float) -> str:
    return f"{s:.0f} s" if s < 120 else f"{s / 60:.0f} min"
