"""pdbfs reproduce: the paper's figures."""
from __future__ import annotations

from ..common import prepare_out


def cmd_reproduce(args):
    """pdbfs reproduce: the paper's figures and the variants' as PNGs, with their table."""
    from pdbfs.studies.paper import reproduce
    figs = [f.strip() for f in args.figures.split(",")] if args.figures else None
    prepare_out(args.out)
    rep = reproduce(args.out, figures=figs, progress=None if not args.quiet else False)
    for name, path in rep.figures.items():
        print(f"wrote {path}")
    print(f"wrote {rep.out / 'table.csv'} and {rep.out / 'table.md'}")


def add_parsers(sub):
    """Add the ``reproduce`` command to the subparsers ``sub``."""
    s = sub.add_parser("reproduce", help="regenerate the paper's Figs. 4-9 and the variant "
                       "rigs' figures as PNGs, with a table of peaks")
    s.add_argument("--out", default="paper-figures", metavar="DIR",
                   help="output folder (default: paper-figures in the current folder)")
    s.add_argument("--figures", default=None,
                   help="comma-separated subset, e.g. fig4,fig6 (default: all)")
    s.add_argument("--quiet", action="store_true", help="no progress bars")
    s.set_defaults(func=cmd_reproduce)
