"""Command line: ``pdbfs simulate | params | export-fmu | sweep | sensitivity | reproduce |
calibrate | design | design-map``.

A thin layer over the Python API that mirrors it: each module here adds its
commands (``add_parsers``) and calls the API; errors print one line naming the
culprit and exit with status 2.

May import anything in pdbfs; nothing imports from here.
"""
from __future__ import annotations

import argparse
import sys

from pdbfs.errors import PdbfsError

from . import app, calibrate, design, reproduce, sensitivity, simulate, sweep

COMMANDS = (simulate, sweep, sensitivity, reproduce, calibrate, design, app)


def build_parser():
    ap = argparse.ArgumentParser(prog="pdbfs", description=__doc__.splitlines()[0])
    from importlib.metadata import PackageNotFoundError, version
    try:
        ver = version("pdbfs")
    except PackageNotFoundError:
        ver = "unknown"
    ap.add_argument("--version", action="version", version=f"pdbfs {ver}")
    sub = ap.add_subparsers(dest="command", required=True)
    for module in COMMANDS:
        module.add_parsers(sub)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        status = args.func(args)
    except PdbfsError as err:
        print(f"pdbfs: error: {err}", file=sys.stderr)
        return 2
    except BrokenPipeError:          # e.g. piped into head: not an error of pdbfs
        sys.stderr.close()
        return 0
    return status or 0

