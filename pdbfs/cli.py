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


def _print_summary(summary):
    from .summary import UNITS
    for k, v in summary.items():
        if isinstance(v, (list, tuple)):   # one value per blow (rigs with repeated impacts)
            vals = ", ".join(f"{x:.6g}" for x in v)
            print(f"  {k:<26} [{vals}] {UNITS.get(k, '')}")
        elif v is None:                    # not defined for this run (e.g. no contact)
            print(f"  {k:<26} {'n/a':>14}")
        else:
            print(f"  {k:<26} {v:>14.6g} {UNITS.get(k, '')}")


def cmd_simulate(args):
    rig = _rig(args.rig)
    # rigs may suggest their own horizon (the drop rig needs about a second)
    t_end = args.t_end if args.t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = args.n_out if args.n_out is not None else getattr(rig, "default_n_out", 2001)
    res = rig.simulate(t_end, n_out=n_out, params=_parse_sets(args.set),
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
        _print_summary(summary)
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


def _parse_sweep_sets(items):
    """--set NAME=V1,V2,... or NAME=START:STOP:NUM (NUM points, ends included)."""
    import numpy as np
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name or not value.strip():
            raise ParameterError(f"--set {item!r}: expected NAME=V1,V2,... or "
                                 "NAME=START:STOP:NUM, e.g. hammer.v0=1.87,2.73,4.23")
        if name in out:
            raise ParameterError(f"--set {name} given twice; list all its values in one --set")
        try:
            if ":" in value:
                a, b, n = value.split(":")
                if int(n) < 1:
                    raise ValueError
                vals = [float(x) for x in np.linspace(float(a), float(b), int(n))]
            else:
                vals = [float(v) for v in value.split(",") if v.strip()]
        except ValueError:
            raise ParameterError(f"--set {item!r}: values must be numbers, comma separated, "
                                 "or START:STOP:NUM with a whole NUM >= 1") from None
        if not vals:
            raise ParameterError(f"--set {item!r}: no values")
        out[name] = vals
    if not out:
        raise ParameterError("sweep: give at least one --set NAME=V1,V2,...")
    return out


def cmd_sweep(args):
    from .sweeps import sweep
    rig = _rig(args.rig)
    values = _parse_sweep_sets(args.set)
    t_end = args.t_end if args.t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = args.n_out if args.n_out is not None else getattr(rig, "default_n_out", 2001)
    res = sweep(rig, values, grid=not args.zip, trajectories=not args.no_plot, t_end=t_end,
                n_out=n_out, params=_parse_sets(args.fix), rtol=args.rtol, method=args.method,
                backend=args.backend, workers=args.workers, progress=None if not args.quiet else False)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    res.to_csv(out / "sweep.csv")
    wrote = [out / "sweep.csv"]
    if not args.no_plot and res.ok:
        import matplotlib
        matplotlib.use("Agg")
        res.plot(path=out / "sweep.png", title=f"rig {res.rig}: {len(res.ok)} points")
        wrote.append(out / "sweep.png")
    if args.json:
        print(json.dumps([{"params": p.params, "summary": p.summary, "error": p.error}
                          for p in res.points]))
    else:
        print(f"rig {res.rig}: {len(res)} points, {len(res.failed)} failed, "
              f"{res.elapsed:.2f} s on {res.workers} process(es)")
        print(res.table())
        print("wrote " + " and ".join(str(w) for w in wrote))
    return 1 if res.failed and args.strict else 0


def cmd_reproduce(args):
    from .reproduce import reproduce
    figs = [f.strip() for f in args.figures.split(",")] if args.figures else None
    rep = reproduce(args.out, figures=figs, progress=None if not args.quiet else False)
    for name, path in rep.figures.items():
        print(f"wrote {path}")
    print(f"wrote {rep.out / 'table.csv'} and {rep.out / 'table.md'}")


def build_parser():
    ap = argparse.ArgumentParser(prog="pdbfs", description=__doc__.splitlines()[0])
    from importlib.metadata import PackageNotFoundError, version
    try:
        ver = version("pdbfs")
    except PackageNotFoundError:
        ver = "unknown"
    ap.add_argument("--version", action="version", version=f"pdbfs {ver}")
    sub = ap.add_subparsers(dest="command", required=True)

    s = sub.add_parser("simulate", help="simulate a rig, write results.csv and a plot")
    s.add_argument("--rig", default="paper", help="rig name (default: paper)")
    s.add_argument("--set", action="append", metavar="NAME=VALUE",
                   help="override a parameter, e.g. --set hammer.v0=4.23 (repeatable)")
    s.add_argument("--t-end", type=float, default=None,
                   help="end time, s (default 0.02; the drop rig: 1.5)")
    s.add_argument("--n-out", type=int, default=None,
                   help="output points (default 2001; the drop rig: 30001)")
    s.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance")
    s.add_argument("--method", default="adams", choices=["adams", "bdf"])
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
    s.set_defaults(func=cmd_export_fmu)

    s = sub.add_parser("sweep", help="simulate a rig over parameter values: CSV of summaries "
                       "and an overlay plot of the pressure")
    s.add_argument("--rig", default="paper", help="rig name (default: paper)")
    s.add_argument("--set", action="append", metavar="NAME=V1,V2,...",
                   help="values of a parameter, comma separated or START:STOP:NUM "
                   "(repeatable; every combination is run)")
    s.add_argument("--zip", action="store_true",
                   help="pair the lists point by point instead of every combination")
    s.add_argument("--fix", action="append", metavar="NAME=VALUE",
                   help="a parameter held at VALUE for every point (repeatable)")
    s.add_argument("--t-end", type=float, default=None, help="end time, s (default 0.02)")
    s.add_argument("--n-out", type=int, default=None, help="output points (default 2001)")
    s.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance")
    s.add_argument("--method", default="adams", choices=["adams", "bdf"])
    s.add_argument("--backend", default="casadi", choices=["casadi", "c"],
                   help="as for simulate (default: casadi)")
    s.add_argument("--workers", type=int, default=None,
                   help="processes (default: automatic, serial for small sweeps)")
    s.add_argument("--out", default="out", help="output folder (default: out)")
    s.add_argument("--no-plot", action="store_true", help="write the CSV only")
    s.add_argument("--json", action="store_true", help="print the points as JSON")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.add_argument("--strict", action="store_true",
                   help="exit with status 1 if any point failed")
    s.set_defaults(func=cmd_sweep)

    s = sub.add_parser("reproduce", help="regenerate the paper's Figs. 4-9 and the variant "
                       "rigs' figures as PNGs, with a table of peaks")
    s.add_argument("--out", default="paper-figures",
                   help="output folder (default: paper-figures)")
    s.add_argument("--figures", default=None,
                   help="comma-separated subset, e.g. fig4,fig6 (default: all)")
    s.add_argument("--quiet", action="store_true", help="no progress bars")
    s.set_defaults(func=cmd_reproduce)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    try:
        status = args.func(args)
    except PdbfsError as err:
        print(f"pdbfs: error: {err}", file=sys.stderr)
        return 2
    return status or 0


if __name__ == "__main__":
    sys.exit(main())
