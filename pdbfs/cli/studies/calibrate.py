"""pdbfs calibrate: fit a rig's unknown parameters to a measured trace."""
from __future__ import annotations

import json
from pathlib import Path

from pdbfs.errors import ParameterError
from pdbfs.files import write_text

from ..common import add_rig_options, parse_sets, prepare_out, rig_by_name
from ..inputs import add_input_option, parse_inputs
from ..progress import Progress


def free_list(text):
    """A comma-separated list of names as a list (empty entries dropped)."""
    return [f.strip() for f in (text or "").split(",") if f.strip()]


def write_outputs(out, stem, result):
    """PNG, CSV and JSON of a calibration or design, written only once it succeeded."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    result.plot(out / f"{stem}.png")
    result.to_csv(out / f"{stem}.csv")
    write_text(out / f"{stem}.json", json.dumps(result.to_dict(), indent=2) + "\n")
    return [out / f"{stem}.{ext}" for ext in ("png", "csv", "json")]


def cmd_calibrate(args):
    """pdbfs calibrate: fit a rig to a measured trace, print the fit, write its files."""
    from pdbfs.studies import calibrate
    if args.seed is not None and args.starts == 1:
        raise ParameterError(f"--seed {args.seed}: only the extra starts of --starts 2 or more "
                             "are drawn at random; the one start is the rig's values")
    rig = rig_by_name(args.rig)
    inputs = parse_inputs(args.input, rig.compile())
    prepare_out(args.out)                  # before the fit: no work lost on a bad --out
    with Progress("calibrating", "simulations") as progress:
        cal = calibrate(rig, args.trace, free_list(args.free), signal=args.signal,
                        fit_offset=args.fit_offset, t_end=args.t_end, bounds=args.bounds,
                        params=parse_sets(args.set), starts=args.starts, seed=args.seed or 0,
                        progress=progress, inputs=inputs)
    wrote = write_outputs(args.out, "calibration", cal) if args.out else []
    if args.json:
        print(json.dumps(cal.to_dict()))
    else:
        print(cal.report())
        if wrote:
            print("wrote " + ", ".join(map(str, wrote)))


def add_parsers(sub):
    """Add the ``calibrate`` command to the subparsers ``sub``."""
    s = sub.add_parser("calibrate", help="fit a rig's unknown parameters to a measured trace "
                       "(CSV: time in s, signal in SI units)")
    add_rig_options(s, sets=False)
    s.add_argument("--trace", required=True, metavar="FILE.csv",
                   help="the measured trace: a header, then time (s) and signal (SI) columns")
    s.add_argument("--free", required=True, metavar="NAME,NAME,...",
                   help="parameters to fit, e.g. oil.k,seal.c,hammer.v0 (hammer.h: a drop height)")
    s.add_argument("--signal", default=None,
                   help="the rig variable the trace measured (default: the rig's pressure)")
    s.add_argument("--fit-offset", action="store_true",
                   help="also fit the trigger time shift and the sensor's zero offset")
    s.add_argument("--bounds", action="append", metavar="NAME=LO:HI",
                   help="bounds of a free parameter (default: a factor 100 either side)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="hold a parameter at VALUE (repeatable)")
    add_input_option(s)
    s.add_argument("--t-end", type=float, default=None,
                   help="simulated horizon, s: the trace's length (the default) or more")
    s.add_argument("--starts", type=int, default=3,
                   help="starts of the optimiser: the rig's values, then a Latin hypercube (default 3)")
    s.add_argument("--seed", type=int, default=None, help="seed of the extra starts (default 0)")
    s.add_argument("--out", default=None,
                   help="folder for calibration.png (trace, fit, residuals), .csv and .json")
    s.add_argument("--json", action="store_true", help="print the result as one JSON object")
    s.set_defaults(func=cmd_calibrate)
