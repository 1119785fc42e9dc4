"""pdbfs simulate | params | export-fmu: one rig, one run."""
from __future__ import annotations

import json
from pathlib import Path

from .common import parse_sets, print_summary, rig_by_name


def cmd_simulate(args):
    rig = rig_by_name(args.rig)
    # rigs may suggest their own horizon (the drop rig needs about a second)
    t_end = args.t_end if args.t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = args.n_out if args.n_out is not None else getattr(rig, "default_n_out", 2001)
    res = rig.simulate(t_end, n_out=n_out, params=parse_sets(args.set),
                       rtol=args.rtol, method=args.method, backend=args.backend)
    summary = res.summary()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res.to_csv(out / "results.csv")
    res.plot(path=out / "results.png")
    if args.json:
        print(json.dumps(summary))
    else:
        print(f"rig {res.rig}: t = 0 .. {res.t[-1]:g} s, {len(res.t)} points")
        print_summary(summary)
        print(f"wrote {out / 'results.csv'} and {out / 'results.png'}")


def cmd_params(args):
    dae = rig_by_name(args.rig).compile()
    if args.json:
        print(json.dumps([p.__dict__ for p in dae.params]))
        return
    print(f"{'parameter':<22} {'default':>12}  {'unit':<10} description")
    for p in dae.params:
        print(f"{p.name:<22} {p.value:>12.6g}  {p.unit:<10} {p.description}")
    for name, (_, info) in dae.calculated.items():
        print(f"{name:<22} {'(computed)':>12}  {info.unit:<10} {info.description}")


def cmd_export_fmu(args):
    rig = rig_by_name(args.rig)
    path = rig.export_fmu(args.output, platforms=args.platforms)
    print(f"wrote {path}")


def add_parsers(sub):
    s = sub.add_parser("simulate", help="simulate a rig, write results.csv and a plot")
    s.add_argument("--rig", default="paper", help="rig name (default: paper)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="override a parameter, e.g. --set hammer.v0=4.23 (repeatable)")
    s.add_argument("--t-end", type=float, default=None,
                   help="end time, s (default 0.02; the drop rig: 1.5)")
    s.add_argument("--n-out", type=int, default=None,
                   help="output points (default 2001; the drop rig: 30001)")
    s.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance")
    s.add_argument("--method", default="auto", choices=["auto", "adams", "bdf"],
                   help="CVODE's method; auto: Adams unless the rig is stiff (default auto)")
    s.add_argument("--backend", default="casadi", choices=["casadi", "c"],
                   help="casadi: SUNDIALS through CasADi (default); c: CVODE compiled "
                   "with the rig's generated C (ODE rigs, needs a C compiler; built once, cached)")
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
    s.add_argument("--platforms", default=None, metavar="P1,P2",
                   help="binaries to build: linux64, win64 (default: every platform this machine can "
                   "build; win64 needs Debian's gcc-mingw-w64-x86-64)")
    s.set_defaults(func=cmd_export_fmu)
