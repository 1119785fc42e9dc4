"""Command line: ``pdbfs simulate | params | export-fmu | export-ssp | modes | linearize |
sweep | sensitivity | reproduce | calibrate | design | design-map | fatigue | campaign | app |
rigs | example-data | prepare-offline``.

A thin layer over the Python API that mirrors it: each command module adds its
commands (``add_parsers``) and calls the API; errors print one line naming the
culprit and exit with status 2. The commands about one rig are in ``rig/``,
those that study it over many runs in ``studies/``; beside them the workbench
(``app``), the example data and the offline set-up, and the helpers they
share (options, input traces, progress, Ctrl-C).

May import anything in pdbfs; nothing imports from here.
"""
from __future__ import annotations

import argparse
import contextlib
import re
import sys
import warnings

from pdbfs.errors import PdbfsError

from . import app, examples, interrupt, offline
from .common import Parser, in_option_words
from .rig import linearize, modes, rigs, simulate, ssp
from .studies import calibrate, campaign, design, fatigue, reproduce, sensitivity, sweep

COMMANDS = (simulate, ssp, modes, linearize, sweep, sensitivity, reproduce, calibrate, design, fatigue,
            campaign, app, rigs, examples, offline)

#: what `pdbfs --help` says above the commands (plain text: argparse shows it as is)
DESCRIPTION = ("Simulate drop-hammer impact test rigs, study them (sweeps, sensitivity, "
               "calibration, design) and export them as FMUs. Commands print their results and "
               "write files only where --out (or -o) says; export-fmu, export-ssp and reproduce, whose "
               "results are files, have a default. `pdbfs COMMAND --help` shows a command's "
               "options.")


def build_parser() -> argparse.ArgumentParser:
    """The ``pdbfs`` argument parser, every command's options included."""
    ap = Parser(prog="pdbfs", description=DESCRIPTION)
    from pdbfs import __version__
    ap.add_argument("--version", action="version", version=f"pdbfs {__version__}",
                    help="print pdbfs's version and exit")
    sub = ap.add_subparsers(dest="command", required=True, title="commands", metavar="COMMAND")
    for module in COMMANDS:
        module.add_parsers(sub)
    return ap


_NUMPY_REPR = re.compile(r"\bnp\.(?:float|int|uint)\d*\(([^()]*)\)")


def plain_text(message) -> str:
    """A message with any numpy scalar repr left in it (``np.float64(3.0)``)
    shown as the number: a net under pdbfs.errors.plain."""
    return _NUMPY_REPR.sub(r"\1", str(message))


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Warnings as one line on stderr, without the source line."""
    print(f"pdbfs: warning: {plain_text(message)}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """Run the command line with ``argv`` (default: sys.argv); returns the exit status."""
    try:
        args = build_parser().parse_args(argv)
    except PdbfsError as err:            # an option given twice (common.Once)
        print(f"pdbfs: error: {err}", file=sys.stderr)
        return 2
    warnings.showwarning = _show_warning
    # the page's server stops on Ctrl-C its own way
    watch = interrupt.watching() if args.command != "app" else contextlib.nullcontext()
    try:
        with watch:
            status = args.func(args)
    except PdbfsError as err:
        print(f"pdbfs: error: {in_option_words(plain_text(err), args)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as stop:  # Ctrl-C: one line, what was kept (a sweep says more)
        interrupt.done()
        print(f"pdbfs: interrupted{': ' + str(stop) if str(stop) else ''}", file=sys.stderr)
        return 130
    except BrokenPipeError:          # e.g. piped into head: not an error of pdbfs
        sys.stderr.close()
        return 0
    return status or 0

