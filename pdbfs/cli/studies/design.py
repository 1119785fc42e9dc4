"""pdbfs design | design-map: the settings that give a wanted pulse."""
from __future__ import annotations

import json
from pathlib import Path

from pdbfs.errors import PdbfsError

from ..common import add_rig_options, parse_sets, prepare_out, rig_by_name
from ..progress import Progress
from .calibrate import free_list, write_outputs


def cmd_design(args):
    """pdbfs design: find the settings for a target pulse, print them, write the files."""
    from pdbfs.studies import design
    rig = rig_by_name(args.rig)
    prepare_out(args.out)
    features = {"peak_pressure": args.peak, "pulse_duration": args.duration,
                "time_of_peak": args.time_of_peak}
    given = {k: v for k, v in features.items() if v is not None}
    if args.target and given:
        raise PdbfsError("give a target curve (--target) or target features "
                         "(--peak/--duration/--time-of-peak), not both")
    target = args.target if args.target else given
    with Progress("designing", "simulations") as progress:
        des = design(rig, target, free=free_list(args.free), bounds=args.bounds,
                     params=parse_sets(args.set), signal=args.signal, t_end=args.t_end,
                     starts=args.starts, progress=progress)
    if args.json:
        print(json.dumps(des.to_dict()))
    else:
        print(des.report())
    if not des.reachable:
        raise PdbfsError(f"design targets not reached: {des.limit}")
    if args.out:
        wrote = write_outputs(args.out, "design", des)
        if not args.json:
            print("wrote " + ", ".join(map(str, wrote)))


def cmd_design_map(args):
    """pdbfs design-map: pulse features over a grid of two parameters."""
    from pdbfs.studies import design_map
    rig = rig_by_name(args.rig)
    prepare_out(args.out)
    m = design_map(rig, args.x, args.y, n=args.n, params=parse_sets(args.set),
                   t_end=args.t_end, backend=args.backend,
                   progress=None if not args.quiet else False)
    out = Path(args.out) if args.out else None
    if out is not None:                  # files only where --out says
        out.mkdir(parents=True, exist_ok=True)
        m.plot(out / "design_map.png")
        m.to_csv(out / "design_map.csv")
    if args.json:
        print(json.dumps({"x": {m.x_name: m.x.tolist()}, "y": {m.y_name: m.y.tolist()},
                          **{k: [[None if v != v else v for v in row] for row in a.tolist()]
                             for k, a in m.values.items()}, "failed": m.failed,
                          "no_pulse": m.no_pulse}))
    else:
        blank = f", {m.no_pulse} without a complete pulse (blank)" if m.no_pulse else ""
        print(f"rig {m.rig}: {m.x.size} x {m.y.size} points, {m.failed} failed{blank}")
        if out is not None:
            print(f"wrote {out / 'design_map.png'} and {out / 'design_map.csv'}")


def add_parsers(sub):
    """Add the ``design`` and ``design-map`` commands to the subparsers ``sub``."""
    s = sub.add_parser("design", help="find the settings whose pulse matches a target curve "
                       "or target features")
    add_rig_options(s, sets=False)
    s.add_argument("--target", default=None, metavar="FILE.csv",
                   help="target curve: a header, then time (s) and signal (SI) columns")
    s.add_argument("--peak", type=float, default=None, help="target peak pressure, Pa")
    s.add_argument("--duration", type=float, default=None,
                   help="target pulse duration, s (time above 1 %% of the peak)")
    s.add_argument("--time-of-peak", type=float, default=None, help="target time of peak, s")
    s.add_argument("--free", required=True, metavar="NAME,NAME,...",
                   help="settings to design, e.g. hammer.v0,oil.k (hammer.h: a drop height)")
    s.add_argument("--bounds", action="append", metavar="NAME=LO:HI",
                   help="bounds of a setting (default: a factor 10 either side of the rig's value)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="hold a parameter at VALUE (repeatable)")
    s.add_argument("--signal", default=None, help="the rig variable (default: its pressure)")
    s.add_argument("--t-end", type=float, default=None, help="simulated horizon, s")
    s.add_argument("--starts", type=int, default=4,
                   help="starts tried when the first does not reach the targets (default 4)")
    s.add_argument("--out", default=None, help="folder for design.png, .csv and .json")
    s.add_argument("--json", action="store_true", help="print the result as one JSON object")
    s.set_defaults(func=cmd_design)

    s = sub.add_parser("design-map", help="contours of peak pressure and pulse duration over "
                       "two settings, from one sweep")
    add_rig_options(s, sets=False)
    s.add_argument("--x", required=True, metavar="NAME=LO:HI", help="first setting and its range")
    s.add_argument("--y", required=True, metavar="NAME=LO:HI", help="second setting and its range")
    s.add_argument("--n", type=int, default=21, help="points per axis (default 21)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="hold a parameter at VALUE (repeatable)")
    s.add_argument("--t-end", type=float, default=0.03, help="simulated horizon, s (default 0.03)")
    s.add_argument("--backend", default="auto", choices=["auto", "casadi", "c"],
                   help="as for simulate (default: auto)")
    s.add_argument("--out", default=None, metavar="DIR",
                   help="folder for design_map.png and .csv (default: none: nothing is written)")
    s.add_argument("--json", action="store_true", help="print the map as JSON")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_design_map)
