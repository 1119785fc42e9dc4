"""pdbfs modes: a rig's natural frequencies, damping ratios and mode shapes
at an operating point; and the --initial option simulate shares."""
from __future__ import annotations

import json

from pdbfs.errors import ParameterError

from ..common import add_rig_options, parse_sets, rig_by_name


def add_initial_option(s):
    """Add ``--initial`` (how the rig starts) to the parser ``s``."""
    s.add_argument("--initial", default=None, metavar="steady|STATE,...",
                   help="start at rest: 'steady' (every state, der(x) = 0, solved) or the "
                   "states to start at rest, comma-separated; der(x) = 0 fixes what x's rate "
                   "depends on, so name a body's position with its velocity "
                   "(breech.s,breech.v) (default: the start values; the rig's free states "
                   "solved from its initial equations)")


def parse_initial(text):
    """``--initial``'s text as simulate()'s ``initial``: None, "steady" or a list of states."""
    if text is None:
        return None
    if text == "steady":
        return "steady"
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise ParameterError(f"--initial {text!r}: give 'steady' or state names")
    return names


def print_initial(res):
    """The solved start, if anything was solved."""
    init = res.initial
    if init is None or not init.solved:
        return
    worst = max(init.residuals.values(), default=0.0)
    print(f"  start solved ({init.iterations} Newton iterations, largest relative residual "
          f"{worst:.2g}):")
    for name in init.solved:
        if name in init.values:
            print(f"    {name:<24} {init.values[name]:>14.8g}")


def parse_at(text):
    """``--at``'s text: "start", "steady" or a time in s."""
    if text in ("start", "steady"):
        return text
    try:
        return float(text)
    except ValueError:
        raise ParameterError(f"--at {text!r}: give start, steady or a time in s") from None


def cmd_modes(args):
    """pdbfs modes: print the rig's modes (or JSON) at the operating point asked for."""
    if args.shape is not None and args.shape < 0:
        raise ParameterError(f"--shape {args.shape}: how many entries of each shape to print; "
                             "give a whole number >= 0")
    if args.shape is not None and args.json:
        raise ParameterError(f"--shape {args.shape}: the JSON output holds every entry of each "
                             "shape; --shape is for the table")
    entries = 4 if args.shape is None else args.shape
    rig = rig_by_name(args.rig)
    params = parse_sets(args.set)
    lin = rig.linearize(parse_at(args.at), params=params, initial=parse_initial(args.initial))
    modes = lin.modes()
    if args.json:
        print(json.dumps({"rig": rig.compile().name, "t": lin.t, "point": lin.point,
                          "kinks": [k.to_dict() for k in lin.kinks],
                          "modes": [m.to_dict() for m in modes]}, allow_nan=False))
        return
    print(f"rig {rig.compile().name}: modes at {args.at}"
          + (f" (t = {lin.t:g} s)" if args.at not in ("start", "steady") else ""))
    if lin.kinks:
        print("  one-sided laws exactly at their kink here:")
        for k in lin.kinks:
            print(f"    {k}")
    print(f"  {'#':>2} {'omega rad/s':>13} {'f Hz':>11} {'damping':>9}  shape (largest entries)")
    for k, m in enumerate(modes, 1):
        damping = "-" if m.damping is None else f"{m.damping:.4g}"
        big = sorted(m.shape.items(), key=lambda kv: -abs(kv[1]))[:entries]
        shape = ", ".join(f"{n} {a:+.3g}" for n, a in big if a != 0.0)
        print(f"  {k:>2} {m.omega:>13.6g} {m.frequency:>11.6g} {damping:>9}  {shape}")


def add_parsers(sub):
    """Add the ``modes`` command to the subparsers ``sub``."""
    s = sub.add_parser("modes", help="natural frequencies, damping and mode shapes of a rig")
    add_rig_options(s)
    s.add_argument("--at", default="start", help="operating point: start, steady, or a time "
                   "of a run in s (default: start)")
    add_initial_option(s)
    s.add_argument("--shape", type=int, default=None, metavar="N",
                   help="how many entries of each shape to print (default 4)")
    s.add_argument("--json", action="store_true", help="print the modes as JSON")
    s.set_defaults(func=cmd_modes)
