"""Command line: ``pdbfs simulate | params | export-fmu | sweep | reproduce``.

Mirrors the Python API; errors print one line naming the culprit and exit 2.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .errors import PdbfsError, ParameterError


def _rig(name):
    from pdbfs.models import RIGS
    if name not in RIGS:
        raise ParameterError(f"unknown rig {name!r}; choose one of {', '.join(RIGS)}")
    return RIGS[name]()


def _parse_sets(items):
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise ParameterError(f"--set {item!r}: expected NAME=VALUE, e.g. hammer.v0=4.23")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            raise ParameterError(f"--set {item!r}: {value!r} is not a number") from None
    return out


def cmd_simulate(args):
    from .summary import UNITS
    rig = _rig(args.rig)
    res = rig.simulate(args.t_end, n_out=args.n_out, params=_parse_sets(args.set),
                       rtol=args.rtol, method=args.method)
    summary = res.summary()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res.to_csv(out / "results.csv")
    res.plot(path=out / "results.png")
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"rig {res.rig}: t = 0 .. {res.t[-1]:g} s, {len(res.t)} points")
        for k, v in summary.items():
            print(f"  {k:<26} {v:>14.6g} {UNITS[k]}")
        print(f"wrote {out / 'results.csv'} and {out / 'results.png'}")


def cmd_params(args):
    dae = _rig(args.rig).compile()
    if args.json:
        print(json.dumps([p.__dict__ for p in dae.params]))
        return
    print(f"{'parameter':<22} {'default':>12}  {'unit':<10} description")
    for p in dae.params:
        print(f"{p.name:<22} {p.value:>12.6g}  {p.unit:<10} {p.description}")
    for name, (_, info) in dae.calculated.items():
        print(f"{name:<22} {'(computed)':>12}  {info.unit:<10} {info.description}")


def cmd_export_fmu(args):
    rig = _rig(args.rig)
    path = rig.export_fmu(args.output)
    print(f"wrote {path}")


def build_parser():
    ap = argparse.ArgumentParser(prog="pdbfs", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="command", required=True)

    s = sub.add_parser("simulate", help="simulate a rig, write results.csv and a plot")
    s.add_argument("--rig", default="paper", help="rig name (default: paper)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="override a parameter, e.g. --set hammer.v0=4.23 (repeatable)")
    s.add_argument("--t-end", type=float, default=0.02, help="end time, s (default 0.02)")
    s.add_argument("--n-out", type=int, default=2001, help="output points (default 2001)")
    s.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance")
    s.add_argument("--method", default="adams", choices=["adams", "bdf"])
    s.add_argument("--out", default="out", help="output folder (default: out)")
    s.add_argument("--json", action="store_true", help="print the summary as JSON")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("params", help="list the parameters of a rig")
    s.add_argument("--rig", default="paper")
    s.add_argument("--json", action="store_true")
    s.set_defaults(func=cmd_params)

    s = sub.add_parser("export-fmu", help="write an FMI 2.0 FMU of a rig")
    s.add_argument("--rig", default="paper")
    s.add_argument("-o", "--output", default="pdbfs.fmu")
    s.set_defaults(func=cmd_export_fmu)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        args.func(args)
    except PdbfsError as err:
        print(f"pdbfs: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
