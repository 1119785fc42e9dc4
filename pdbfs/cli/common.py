"""What every command shares: one set of options (the same name for the same
thing everywhere, each given at most once), rig names, --set parsing, output
folders checked before any work, printing a summary."""
from __future__ import annotations

import argparse
import re
import tempfile
from pathlib import Path

from pdbfs.errors import ParameterError


# -- an option given twice ------------------------------------------------------------
def twice(option: str, first, second) -> str:
    """The message of an option (or a name in one) given twice."""
    return f"{option} given twice ({_shown(first)} and {_shown(second)}); give it once"


class Once(argparse._StoreAction):
    """argparse's ``store``, refusing a second value: the last would win
    without a word (repeatable options are ``append`` and check their names)."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = getattr(namespace, "_given", None)      # what this parse was given so far
        if given is None:
            given = {}
            setattr(namespace, "_given", given)
        if self.dest in given:
            name = max(self.option_strings, key=len) if self.option_strings else self.dest
            raise ParameterError(twice(name, given[self.dest], values))
        given[self.dest] = values
        setattr(namespace, self.dest, values)


class Parser(argparse.ArgumentParser):
    """An ArgumentParser (and its commands' parsers) whose options of one
    value take it once (:class:`Once`), and that reads a negative number in
    scientific notation (``--atol -1e-3``) as a value, as it reads ``-0.001``
    (not as an option: its own message is then the value's)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.register("action", None, Once)
        self.register("action", "store", Once)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


#: the API's names of settings in its messages (``t_end = ...``) and the options that give them
OPTIONS = {"t_end": "--t-end", "n_out": "--n-out", "rtol": "--rtol", "atol": "--atol",
           "max_step": "--max-step", "starts": "--starts"}


def in_option_words(message: str, args) -> str:
    """An API message that begins with settings (``t_end = 1e-12 s with
    n_out = 2001: ...``) as the command line names them (``--t-end 1e-12 s
    with --n-out 2001: ...``), for the options the command has."""
    head, sep, rest = message.partition(": ")
    words = head.split(" with ")
    for k, word in enumerate(words):
        name, eq, value = word.partition(" = ")
        if eq and name in OPTIONS and hasattr(args, name):
            words[k] = f"{OPTIONS[name]} {value}"
    return " with ".join(words) + sep + rest


# -- options ---------------------------------------------------------------------------
#: what --rig takes, in every command
RIG_HELP = ("a rig: a name of `pdbfs rigs` (default: paper), or a rig of your own, FILE.py:NAME or "
            "MODULE:NAME, NAME a Rig class or a function returning a rig (`pdbfs params --rig RIG` "
            "lists its parameters)")


def add_rig_options(s, sets=True, set_help=None):
    """--rig NAME, and --set NAME=VALUE (parameters held at a value)."""
    s.add_argument("--rig", default="paper", metavar="RIG", help=RIG_HELP)
    if sets:
        s.add_argument("--set", action="append", metavar="NAME=VALUE",
                       help=set_help or "hold a parameter at a value, e.g. --set hammer.v0=4.23 "
                       "(repeatable)")


def add_run_options(s, t_end=None, n_out=True, backend="auto", method="auto", rtol=True,
                    max_step=False):
    """How a rig is simulated: horizon, output points, tolerance, method, back end (and the
    longest step, where ``max_step``)."""
    default = f"default {t_end}" if t_end is not None else "default: the rig's own, 0.02 for " \
        "the paper rig, 1.5 for the drop rig"
    s.add_argument("--t-end", type=float, default=t_end, help=f"simulated time, s ({default})")
    if n_out:
        s.add_argument("--n-out", type=int, default=None,
                       help="output points (default: the rig's own, 2001; the drop rig: 30001)")
    if rtol:
        s.add_argument("--rtol", type=float, default=None,
                       help="relative tolerance (default 1e-8; 5e-8 for the explicit method)")
        s.add_argument("--atol", type=float, default=None,
                       help="absolute tolerance, in each state's unit (default 1e-10, and "
                       "1e-2 x rtol below rtol 1e-8: a tighter rtol converges on small signals)")
    if max_step:
        s.add_argument("--max-step", type=float, default=None, metavar="S",
                       help="the longest step the integrator may take, s (default: no limit; "
                       "a short one makes sure a brief feature of an input is seen)")
    if method:
        s.add_argument("--method", default=method, choices=["auto", "adams", "bdf", "erk"],
                       help="integration method: CVODE's adams or bdf, or erk (explicit "
                       "Runge-Kutta of order 8, compiled backend); auto: the cheapest for the "
                       f"run by an estimate from the rig's modes (default {method})")
    s.add_argument("--backend", default=backend, choices=["auto", "casadi", "c"],
                   help="casadi: SUNDIALS through CasADi; c: the rig's generated C compiled "
                   "with pdbfs's integrators (ODE rigs, built once by zig cc, cached); "
                   f"auto: c where it can be built, else casadi (default {backend})")


def add_output_options(s, out=None, what="results", json_help="print the result as JSON"):
    """Add ``--out`` (the output folder; default ``out``, None: nothing is written) and
    ``--json`` to the parser ``s``."""
    s.add_argument("--out", default=out, metavar="DIR", help=f"output folder for the {what}"
                   + (f" (default: {out})" if out else " (default: none: nothing is written)"))
    s.add_argument("--json", action="store_true", help=json_help)


def horizon(args, rig):
    """--t-end and --n-out, or the rig's own experiment."""
    t_end = args.t_end if args.t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = getattr(args, "n_out", None)
    n_out = n_out if n_out is not None else getattr(rig, "default_n_out", 2001)
    return t_end, n_out


# -- checks before any work --------------------------------------------------------------
def prepare_out(path, option="--out") -> Path | None:
    """The output folder, checked now but made only when something is
    written: refused with one line if it is a file or cannot be made or
    written, so that no work is lost later and a refused run leaves nothing."""
    if path is None:
        return None
    if not str(path).strip():       # Path("") is the current folder: never what was meant
        raise ParameterError(f"{option} {path!r}: empty; name a folder ('.' for the current one)")
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise ParameterError(f"{option} {path}: exists and is not a folder")
    base = out
    while not base.exists():                       # the nearest folder that exists
        base = base.parent
    if not base.is_dir():
        raise ParameterError(f"{option} {path}: {base} is not a folder")
    _try_writing(base, option, path)
    return out


def check_output_file(path, option="-o") -> Path:
    """A file about to be written: not a folder, in a writable folder."""
    p = Path(path)
    if not str(path).strip():
        raise ParameterError(f"{option} '{path}': an empty name; name the file to write")
    if p.is_dir():
        raise ParameterError(f"{option} {path}: is a folder; name the file to write")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ParameterError(f"{option} {path}: the folder {parent} does not exist")
    _try_writing(parent, option, path)
    return p


def _try_writing(folder, option, path):
    """A file made and removed in ``folder`` (root passes os.access everywhere)."""
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as err:
        raise ParameterError(f"{option} {path}: cannot write in {folder} "
                             f"({err.strerror or err})") from None


# -- values ---------------------------------------------------------------------------
def rig_by_name(name):
    """A new rig of ``RIGS[name]``, or the user's rig ``name`` names
    (``FILE.py:NAME``, ``MODULE:NAME``; pdbfs.models.rig_from); an unknown
    name or a rig that cannot be loaded is a ParameterError of one line."""
    from pdbfs.models import rig_from
    return rig_from(name, "--rig")


def parse_sets(items):
    """{name: value} from --set NAME=VALUE items; a name given twice is
    refused (the last would win without a word)."""
    pairs = []
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name.strip():
            raise ParameterError(f"--set {item!r}: expected NAME=VALUE, e.g. hammer.v0=4.23")
        try:
            pairs.append((name.strip(), float(value)))
        except ValueError:
            raise ParameterError(f"--set {item!r}: {value!r} is not a number") from None
    return unique(pairs, "--set")


def unique(pairs, option) -> dict:
    """A dict of (name, value) pairs, refusing a name given twice."""
    out = {}
    for name, value in pairs:
        if name in out:
            raise ParameterError(twice(f"{option} {name}", out[name], value))
        out[name] = value
    return out


def _shown(value) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple):
        return ":".join(_shown(v) for v in value)
    return str(value)


def print_summary(summary):
    """Print a run's summary, one key a line with its unit."""
    from pdbfs.simulation import SUMMARY_UNITS
    # a count or a ratio has the unit "1": printed as the bare number
    units = {k: ("" if u == "1" else " " + u) for k, u in SUMMARY_UNITS.items()}
    for k, v in summary.items():
        if isinstance(v, bool):
            print(f"  {k:<26} {'yes' if v else 'no':>14}")
        elif isinstance(v, (list, tuple)):   # one value per blow (rigs with repeated impacts)
            vals = ", ".join("n/a" if x is None else f"{x:.6g}" for x in v)
            print(f"  {k:<26} [{vals}]{units.get(k, '')}")
        elif isinstance(v, dict):
            continue
        elif v is None:                    # not defined for this run (e.g. no contact)
            print(f"  {k:<26} {'n/a':>14}")
        else:
            print(f"  {k:<26} {v:>14.6g}{units.get(k, '')}")
