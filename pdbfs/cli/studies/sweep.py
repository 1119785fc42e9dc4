"""pdbfs sweep: a rig over many parameter values."""
from __future__ import annotations

import json

from pdbfs.errors import ParameterError, require_extra

from ..common import (add_output_options, add_rig_options, add_run_options, horizon,
                      prepare_out, rig_by_name, unique)
from ..inputs import add_input_option, parse_inputs


def parse_sweep_sets(items, required=True):
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
    if not out and required:
        raise ParameterError("sweep: give at least one --set NAME=V1,V2,...")
    return out


#: a sweep this small keeps its trajectories for the overlay plot (unless --no-plot)
PLOT_MAX_POINTS = 50
#: a sweep this small also writes one sweep.csv beside its chunks
CSV_MAX_POINTS = 100_000


def points_from_args(args):
    """The sweep's points and the parameters held fixed: --set lists (a grid,
    or --zip; a single value holds a parameter), or --sample KIND:N over
    --range / --dist (--set NAME=VALUE then holds parameters)."""
    from pdbfs.studies.sweeps.sampling import Grid, Sample, parse_dist, parse_range, parse_sample
    if args.sample and args.zip:
        raise ParameterError("--zip pairs the --set lists point by point; a --sample has no "
                             "lists to pair (leave --zip out)")
    if args.seed is not None and not args.sample:
        raise ParameterError(f"--seed {args.seed}: only a --sample (lhs:N, sobol:N, mc:N) is "
                             "drawn at random; a --set grid has no seed")
    if args.sample:
        fixed = {}
        for name, vals in (parse_sweep_sets(args.set, required=False)).items():
            if len(vals) != 1:
                raise ParameterError(f"--set {name}: with --sample, --set holds a parameter at "
                                     "one value; sample it with --range or --dist instead")
            fixed[name] = vals[0]
        kind, n = parse_sample(args.sample)
        ranges = unique((parse_range(r) for r in args.range or []), "--range")
        dists = unique((parse_dist(d) for d in args.dist or []), "--dist")
        return Sample(kind, n, ranges, dists, seed=args.seed or 0), fixed
    if args.range or args.dist:
        raise ParameterError("--range and --dist need --sample (lhs:N, sobol:N or mc:N)")
    return Grid(parse_sweep_sets(args.set), zip=args.zip), {}


def cmd_sweep(args):
    """pdbfs sweep: simulate a rig over many parameter values, locally or on Dask."""
    from pdbfs.studies import sweep
    from pdbfs.studies.sweeps.cluster import close, connect
    check_extras(args)
    rig = rig_by_name(args.rig)
    inputs = parse_inputs(args.input, rig.compile())
    points, fixed = points_from_args(args)
    t_end, n_out = horizon(args, rig)
    if args.dask and args.workers is not None:
        raise ParameterError(f"--workers {args.workers}: with --dask the cluster's workers run "
                             "the sweep (start them with as many threads as wanted)")
    # a small grid keeps its trajectories for the overlay plot, in memory; the rest
    # streams its chunks to --out (and resumes)
    plot = args.out is not None and not args.no_plot and not args.sample and \
        points.n <= PLOT_MAX_POINTS and not args.dask
    if plot and args.format is not None:
        raise ParameterError(f"--format {args.format}: this sweep of {points.n} points runs in "
                             "memory for its plot and writes no chunk files (its table is "
                             "sweep.csv); add --no-plot to write chunk files")
    out = prepare_out(args.out)
    if plot:
        from pdbfs.studies.sweeps.store import refuse_other_sweep
        refuse_other_sweep(out, args.overwrite)
    client = connect(args.dask) if args.dask else None
    try:
        res = sweep(rig, points, trajectories=plot, t_end=t_end, n_out=n_out,
                    params=fixed, rtol=args.rtol, atol=args.atol, method=args.method,
                    max_step=args.max_step,
                    backend=args.backend, workers=args.workers, client=client,
                    out=None if plot or out is None else out,
                    format=None if plot else args.format, chunk_size=args.chunk,
                    overwrite=args.overwrite and not plot,
                    progress=None if not args.quiet else False, inputs=inputs)
    except KeyboardInterrupt:
        raise KeyboardInterrupt(interrupted(out, plot, points.n)) from None
    finally:
        if client is not None:
            close(client)
    wrote = [out] if res.store is not None else []
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    if out is not None and len(res) <= CSV_MAX_POINTS:
        res.to_csv(out / "sweep.csv")
        wrote.append(out / "sweep.csv")
    if plot and res.ok:
        import matplotlib
        matplotlib.use("Agg")
        res.plot(path=out / "sweep.png", title=f"rig {res.rig}: {len(res.ok)} points")
        wrote.append(out / "sweep.png")
    failed = res.n_failed
    if args.json:
        doc = {"rig": res.rig, "n_points": len(res), "failed": failed, "computed": res.computed,
               "elapsed": res.elapsed,
               "where": res.where, "folder": str(out) if res.store is not None else None}
        if len(res) <= 10_000:
            doc["points"] = [{"params": p.params, "summary": p.summary, "error": p.error}
                             for p in res.points]
        print(json.dumps(doc))
    else:
        resumed = len(res) - res.computed
        print(f"rig {res.rig}: {len(res)} points, {failed} failed; {res.computed} computed in "
              f"{res.elapsed:.2f} s on {res.where} ({res.computed / max(res.elapsed, 1e-9):.0f} "
              "points/s)" + (f", {resumed} found done in {args.out}" if resumed else ""))
        print(res.table())
        if wrote:
            print("wrote " + ", ".join(str(w) for w in wrote))
    return 1 if failed and args.strict else 0


def check_extras(args):
    """--dask and --format parquet without their extras: refused before any work."""
    if args.dask:
        require_extra("dask", "--dask")
    if args.format == "parquet":
        require_extra("parquet", "--format parquet")


def interrupted(out, in_memory, n) -> str:
    """What a Ctrl-C leaves: the points saved in --out, and how to go on."""
    if in_memory or out is None:
        return (f"the sweep of {n} points kept nothing (it ran in memory: "
                + ("small sweeps do" if out is not None else "no --out") + ")")
    from pdbfs.studies.sweeps.store import saved_points
    done = saved_points(out)
    return (f"{done} of {n} points are saved in {out}; the same command resumes "
            "from there")


def add_parsers(sub):
    """Add the ``sweep`` command to the subparsers ``sub``."""
    s = sub.add_parser("sweep", help="simulate a rig over a grid or a sample of parameter "
                       "values, locally or on a Dask cluster; summaries to CSV/Parquet")
    add_rig_options(s, set_help="values of a parameter, comma separated or START:STOP:NUM "
                    "(repeatable; every combination is run); one value holds it there")
    s.add_argument("--zip", action="store_true",
                   help="pair the lists point by point instead of every combination")
    s.add_argument("--sample", metavar="KIND:N",
                   help="N points: lhs (Latin hypercube), sobol, or mc (Monte Carlo)")
    s.add_argument("--range", action="append", metavar="NAME=LO:HI[:log]",
                   help="a sampled parameter's range (uniform; :log for its logarithm)")
    s.add_argument("--dist", action="append", metavar="NAME=normal:MEAN:SD",
                   help="a Monte Carlo parameter's distribution: normal:MEAN:SD, "
                   "uniform:LO:HI or lognormal:MEDIAN:SIGMA (with --sample mc:N)")
    s.add_argument("--seed", type=int, default=None, help="seed of the sample (default 0)")
    add_input_option(s)
    add_run_options(s, max_step=True)
    s.add_argument("--workers", type=int, default=None,
                   help="threads or processes on this machine (default: one per core)")
    s.add_argument("--dask", metavar="ADDRESS",
                   help="run on the Dask scheduler at ADDRESS (tcp://HOST:8786), or 'local' "
                   "for a LocalCluster here")
    add_output_options(s, what="manifest and chunk files of the sweep (rerun the same "
                       "command to resume), sweep.csv, sweep.png; without it the sweep runs in "
                       "memory and prints its table")
    s.add_argument("--format", default=None, choices=["parquet", "csv"],
                   help="format of the chunk files (default: parquet where pyarrow, the extra "
                   "pdbfs[parquet], is installed, else csv)")
    s.add_argument("--chunk", type=int, default=None, help="points per chunk (default: automatic)")
    s.add_argument("--overwrite", action="store_true",
                   help="replace another sweep found in --out instead of refusing")
    s.add_argument("--no-plot", action="store_true", help="no overlay plot of the pressure")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.add_argument("--strict", action="store_true",
                   help="exit with status 1 if any point failed")
    s.set_defaults(func=cmd_sweep)
