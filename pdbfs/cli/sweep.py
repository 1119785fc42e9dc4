"""pdbfs sweep: a rig over many parameter values."""
from __future__ import annotations

import json
from pathlib import Path

from pdbfs.errors import ParameterError

from .common import parse_sets, rig_by_name


def parse_sweep_sets(items):
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
    from pdbfs.studies import sweep
    rig = rig_by_name(args.rig)
    values = parse_sweep_sets(args.set)
    t_end = args.t_end if args.t_end is not None else getattr(rig, "default_t_end", 0.02)
    n_out = args.n_out if args.n_out is not None else getattr(rig, "default_n_out", 2001)
    res = sweep(rig, values, grid=not args.zip, trajectories=not args.no_plot, t_end=t_end,
                n_out=n_out, params=parse_sets(args.fix), rtol=args.rtol, method=args.method,
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


def add_parsers(sub):
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
