"""What the command-line tests share: the command run as a user runs it
(a new process), and the check of a refusal (one line, exit status 2)."""
from __future__ import annotations

import os
import subprocess
import sys


def cli(*args, cwd, env=None, timeout=300):
    """``pdbfs ARGS`` in ``cwd`` (``env``: variables added to this process's)."""
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=timeout,
                          env=None if env is None else {**os.environ, **env})


def one_line(r, *words):
    """The refusal's one line, checked: exit status 2, ``pdbfs: error:``, ``words`` in it."""
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("pdbfs: error: "), r.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    return lines[0]
