"""pdbfs sensitivity: Sobol' indices of the pulse features."""
from __future__ import annotations

import json

from pdbfs.errors import require_extra
from pdbfs.files import write_text

from ..common import (add_output_options, add_rig_options, add_run_options, parse_sets,
                      prepare_out, rig_by_name, unique)


def cmd_sensitivity(args):
    """pdbfs sensitivity: Sobol' indices of the summary over parameter ranges."""
    require_extra("sensitivity", "pdbfs sensitivity")
    if args.dask:
        require_extra("dask", "--dask")
    from pdbfs.studies import sensitivity
    from pdbfs.studies.sweeps.cluster import close, connect
    from pdbfs.studies.sweeps.sampling import parse_range
    rig = rig_by_name(args.rig)
    out = prepare_out(args.out)
    ranges = unique((parse_range(r) for r in args.range or []), "--range")
    outputs = [o.strip() for o in args.outputs.split(",") if o.strip()]
    client = connect(args.dask) if args.dask else None
    try:
        s = sensitivity(rig, ranges, n=args.n, outputs=outputs, params=parse_sets(args.set),
                        backend=args.backend, client=client, seed=args.seed, t_end=args.t_end,
                        progress=None if not args.quiet else False)
    finally:
        if client is not None:
            close(client)
    if out is not None:                  # files only where --out says
        out.mkdir(parents=True, exist_ok=True)
        s.plot(out / "sensitivity.png")
        write_text(out / "sensitivity.json", json.dumps(s.to_dict(), indent=1) + "\n")
        write_text(out / "sensitivity.txt", s.table() + "\n")
    if args.json:
        print(json.dumps(s.to_dict()))
    else:
        print(s.table())
        if out is not None:
            print(f"wrote {out / 'sensitivity.png'}, {out / 'sensitivity.json'}, "
                  f"{out / 'sensitivity.txt'}")


def add_parsers(sub):
    """Add the ``sensitivity`` command to the subparsers ``sub``."""
    s = sub.add_parser("sensitivity", help="Sobol' indices (SALib) of peak pressure, time of "
                       "peak and pulse duration over parameter ranges")
    add_rig_options(s)
    s.add_argument("--range", action="append", metavar="NAME=LO:HI[:log]",
                   help="a parameter's range (repeatable; :log samples its logarithm)")
    s.add_argument("--n", type=int, default=4096,
                   help="base sample size N, a power of 2: N (D + 2) simulations (default 4096)")
    s.add_argument("--outputs", default="peak_pressure,time_of_peak,pulse_duration",
                   help="summary values to analyse (comma separated)")
    add_run_options(s, t_end=0.03, n_out=False, backend="auto", method=False, rtol=False)
    s.add_argument("--dask", metavar="ADDRESS", help="a Dask scheduler, or 'local'")
    s.add_argument("--seed", type=int, default=0, help="seed of the sample")
    add_output_options(s, what="sensitivity.png, .json and .txt",
                       json_help="print the indices as JSON")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=cmd_sensitivity)
