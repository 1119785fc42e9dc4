"""Progress of a long step of a command, on stderr where it is a terminal
(as a sweep's bar): nothing for work that ends within AFTER seconds; then
what is done so far, rewritten in place every EVERY seconds and cleared at
the end, so that no command works for minutes without a word and what is
left on the screen is the command's own output (or its one-line error)."""
from __future__ import annotations

import sys
import time

#: seconds of work before the first word
AFTER = 2.0
#: seconds between two updates of the line
EVERY = 0.5


class Progress:
    """A callable ``progress(done, total=None)`` for ``label`` ("writing
    results.csv", "calibrating"); ``unit`` names what is counted. Use it as a
    context manager: leaving the block clears the line. Silent where
    ``stream`` (stderr) is no terminal."""

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
        if not self.tty or elapsed < AFTER or (self.last is not None
                                               and now - self.last < EVERY):
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
        self.stream.write(f"\r{text}\033[K")
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
