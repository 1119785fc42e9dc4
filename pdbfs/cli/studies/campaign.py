"""pdbfs campaign: a rig's blows one after another, each from the
temperatures the blows before left, with a schedule of settings and an
operator's rule; the table of blows, the totals, the damage and the life."""
from __future__ import annotations

import math

from pdbfs.errors import ParameterError, require_extra

from ..common import (add_output_options, add_rig_options, add_run_options, parse_sets,
                      prepare_out, rig_by_name, unique)
from ..progress import Progress
from .fatigue import add_breech_options, breech_of


def cmd_campaign(args):
    """pdbfs campaign: N blows, one every S seconds; their table, totals and plot."""
    from pdbfs.studies.campaign import campaign, read_schedule
    if args.format == "parquet":
        require_extra("parquet", "--format parquet")
    if args.out is None and (args.format is not None or args.overwrite):
        raise ParameterError(f"{'--format' if args.format else '--overwrite'} is about the "
                             "files in --out; without --out nothing is written")
    rig = rig_by_name(args.rig)
    breech = breech_of(args)
    temperatures = parse_temperatures(args.temperature)
    schedule = read_schedule(args.schedule) if args.schedule is not None else None
    out = prepare_out(args.out)
    label = f"campaign of rig {args.rig}"
    try:
        with Progress(label, "blows") as progress:
            res = campaign(rig, args.blows, args.period, schedule=schedule, rule=args.rule,
                           params=parse_sets(args.set), temperatures=temperatures,
                           breech=breech, damage=args.damage, check_every=args.check_every,
                           t_blow=args.t_end, oil=args.oil, rtol=args.rtol, atol=args.atol,
                           method=args.method, backend=args.backend, out=out,
                           format=args.format, chunk_size=args.chunk, overwrite=args.overwrite,
                           progress=None if args.quiet else progress)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(interrupted(out, args.blows)) from None
    wrote = []
    if out is not None:
        wrote.append(out)
        res.to_csv(out / "campaign.csv")
        wrote.append(out / "campaign.csv")
        if not args.no_plot:
            import matplotlib
            matplotlib.use("Agg")
            res.plot(path=out / "campaign.png")
            wrote.append(out / "campaign.png")
    if args.json:
        print(res.to_json())
        return 0
    resumed = len(res) - res.computed
    print(f"rig {res.rig}: {len(res)} blows, one every {res.period:g} s (each simulated over "
          f"{res.t_blow:g} s); {res.computed} computed in {res.elapsed:.2f} s"
          + (f", {resumed} found done in {out}" if resumed else ""))
    print(res.text())
    if wrote:
        print("wrote " + ", ".join(str(w) for w in wrote))
    return 0


def parse_temperatures(items) -> dict:
    """{state: K} from --temperature NAME=K items."""
    pairs = []
    for item in items or []:
        name, sep, value = item.partition("=")
        try:
            v = float(value)
        except ValueError:
            v = math.nan
        if not sep or not name.strip() or not math.isfinite(v):
            raise ParameterError(f"--temperature {item!r}: expected NAME=KELVIN, e.g. "
                                 "oil_heat.T=303.15")
        pairs.append((name.strip(), v))
    return unique(pairs, "--temperature")


def interrupted(out, n) -> str:
    """What a Ctrl-C leaves: the blows saved in --out, and how to go on."""
    if out is None:
        return f"the campaign of {n} blows kept nothing (no --out)"
    from pdbfs.studies.campaign.run import resumed
    return f"{resumed(out)} of {n} blows are saved in {out}; the same command resumes from there"


def add_parsers(sub):
    """Add the ``campaign`` command to the subparsers ``sub``."""
    s = sub.add_parser("campaign", help="a fatigue campaign: N blows, one every S seconds, each "
                       "from the temperatures the blows before left; per-blow table, drift, "
                       "damage and life")
    add_rig_options(s)
    s.add_argument("--blows", type=int, required=True, metavar="N", help="the number of blows")
    s.add_argument("--period", type=float, required=True, metavar="S",
                   help="the time from one blow to the next, s (longer than --t-end)")
    add_run_options(s, n_out=False)
    s.add_argument("--schedule", metavar="FILE",
                   help="per-blow settings: a CSV with a column per parameter (or drop_height, "
                   "m), one row per blow, at least --blows rows")
    s.add_argument("--rule", metavar="NAME:ARGS",
                   help="an operator's rule adjusting the next blow: hold-peak:LOW:HIGH[:TARGET] "
                   "(Pa) scales the striker's speed (or drop height) when a peak leaves the band")
    s.add_argument("--temperature", action="append", metavar="NAME=K",
                   help="a heat capacitor's temperature at the start, K, e.g. oil_heat.T=303.15 "
                   "(repeatable; default: the rig's own)")
    s.add_argument("--oil", default=None, metavar="NAME",
                   help="the heat capacitor's temperature reported as the oil's (default "
                   "oil_heat.T where the rig has it)")
    add_breech_options(s)
    s.add_argument("--damage", default="peak", choices=["peak", "history"],
                   help="each blow's damage from its peak pressure (default), or from the "
                   "rainflow count of its whole history (several times slower)")
    s.add_argument("--check-every", type=int, default=500, metavar="K",
                   help="read a blow's whole history too every K blows from the first, and "
                   "the last (default 500; 0: none)")
    add_output_options(s, what="manifest and chunk files of the campaign (rerun the same "
                       "command to resume), campaign.csv and campaign.png")
    s.add_argument("--format", default=None, choices=["parquet", "csv"],
                   help="format of the chunk files (default: parquet where pyarrow, the extra "
                   "pdbfs[parquet], is installed, else csv)")
    s.add_argument("--chunk", type=int, default=1000, metavar="N",
                   help="blows per chunk file (default 1000)")
    s.add_argument("--overwrite", action="store_true",
                   help="replace another campaign found in --out instead of refusing")
    s.add_argument("--no-plot", action="store_true", help="no campaign.png")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_campaign)
