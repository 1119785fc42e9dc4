"""pdbfs simulate | params | export-fmu: one rig, one run."""
from __future__ import annotations

import json

from ..common import (add_output_options, add_rig_options, add_run_options, check_output_file,
                      horizon, parse_sets, prepare_out, print_summary, rig_by_name)
from ..inputs import add_input_option, parse_inputs
from ..progress import Progress
from .modes import add_initial_option, parse_initial, print_initial


def cmd_simulate(args):
    """pdbfs simulate: one run of a rig, its summary printed (or JSON), results written."""
    rig = rig_by_name(args.rig)
    params = parse_sets(args.set)
    inputs = parse_inputs(args.input, rig.compile())
    out = prepare_out(args.out)
    # rigs may suggest their own horizon (the drop rig needs about a second)
    t_end, n_out = horizon(args, rig)
    initial = parse_initial(args.initial)
    check_room(out, n_out, rig.compile())
    extra = {"inputs": inputs} if inputs else {}
    res = rig.simulate(t_end, n_out=n_out, params=params, initial=initial,
                       rtol=args.rtol, atol=args.atol, method=args.method, max_step=args.max_step,
                       backend=args.backend, **extra)
    summary = res.summary()
    if out is not None:                  # files only where --out says
        out.mkdir(parents=True, exist_ok=True)
        with Progress(f"writing {out / 'results.csv'}", "rows") as progress:
            res.to_csv(out / "results.csv", progress=progress)
        res.plot(path=out / "results.png", title=_title(args.rig, res))
    if args.json:
        solved = {"initial": res.initial.to_dict()} if res.initial.solved else {}
        print(json.dumps({**summary, "stats": res.stats, **solved}, allow_nan=False))
    else:
        print(f"rig {res.rig}: t = 0 .. {res.t[-1]:g} s, {len(res.t)} points")
        print_initial(res)
        print_summary(summary)
        st = res.stats
        print(f"  solver: {st.get('method')} ({st.get('backend')}), {st.get('steps')} steps, "
              f"{st.get('rhs_evals')} right-hand sides, {st.get('wall_time', 0) * 1e3:.1f} ms")
        if out is not None:
            print(f"wrote {out / 'results.csv'} and {out / 'results.png'}")


#: characters of a value in results.csv, about (``repr`` of a float and a comma)
CSV_CHARS = 18


def check_room(out, n_rows, dae):
    """Refuse, before the run, output points that cannot fit in memory (as
    simulate() would), then a results.csv larger than the room left on the
    disk of ``out`` (it is written a block of rows at a time: memory does not
    bound it, the disk does)."""
    import shutil

    from pdbfs.errors import ParameterError
    from pdbfs.simulation.setup.memory import plain_bytes, require, run_bytes
    if not isinstance(n_rows, int) or n_rows < 100_000:
        return                         # small, or refused by simulate() itself
    require(run_bytes(dae, n_rows), f"rig {dae.name}: {n_rows} output points",
            "ask for fewer (n_out, --n-out)")
    if out is None:
        return                         # no results.csv to write
    need = float(n_rows) * (len(dae.y_names) + 1) * CSV_CHARS
    base = out
    while not base.exists():
        base = base.parent
    free = shutil.disk_usage(base).free
    if need > free:
        raise ParameterError(f"--n-out {n_rows}: {out / 'results.csv'} would take about "
                             f"{plain_bytes(need)}, and {plain_bytes(free)} are free on its "
                             "disk; ask for fewer output points")


def _title(name, res):
    """The plot's title: the rig as the command line names it (and as its FMU does)."""
    from pdbfs.simulation.results.plotting import _title as describe
    return describe(res).replace(f"rig {res.rig}", f"rig {name} ({res.rig})", 1)


def cmd_params(args):
    """pdbfs params: every parameter of a rig with its value, unit and description."""
    dae = rig_by_name(args.rig).compile()
    if args.json:
        print(json.dumps([p.__dict__ for p in dae.params]))
        return
    print(f"{'parameter':<22} {'default':>12}  {'unit':<10} description")
    for p in dae.params:
        print(f"{p.name:<22} {p.value:>12.6g}  {p.unit:<10} {p.description}")
    for name, (_, info) in dae.calculated.items():
        print(f"{name:<22} {'(computed)':>12}  {info.unit:<10} {info.description}")
    if dae.inputs:           # not parameters: given to a run with --input NAME=FILE.csv
        print(f"\n{'input':<22} {'start':>12}  {'unit':<10} description")
        for u in dae.inputs:
            print(f"{u.name:<22} {u.start:>12.6g}  {u.unit:<10} {u.description}")


def cmd_export_fmu(args):
    """pdbfs export-fmu: write a rig's FMU."""
    from pdbfs.fmu import check_fmu_name
    rig = rig_by_name(args.rig)
    check_fmu_name(args.output)        # (an empty name is not the current folder)
    check_output_file(args.output)
    version = int(args.fmi_version) if args.fmi_version in ("2", "3") else args.fmi_version  # else refused
    path = rig.export_fmu(args.output, fmi_version=version, platforms=args.platforms, author=args.author,
                          license=args.license, copyright=args.copyright)
    print(f"wrote {path}")


def add_parsers(sub):
    """Add the ``simulate``, ``params`` and ``export-fmu`` commands to the subparsers ``sub``."""
    s = sub.add_parser("simulate", help="simulate a rig and print its summary; with --out, "
                       "write results.csv and a plot")
    add_rig_options(s)
    add_run_options(s, max_step=True)
    add_initial_option(s)
    add_input_option(s)
    add_output_options(s, json_help="print the summary, the solver statistics and (if it "
                       "was solved) the start as JSON")
    s.set_defaults(func=cmd_simulate)

    s = sub.add_parser("params", help="list the parameters of a rig")
    add_rig_options(s, sets=False)
    s.add_argument("--json", action="store_true",
                   help="print the parameters (name, value, unit, description) as JSON")
    s.set_defaults(func=cmd_params)

    s = sub.add_parser("export-fmu", help="write an FMI 2.0 or 3.0 FMU of a rig")
    add_rig_options(s, sets=False)
    s.add_argument("-o", "--output", default="pdbfs.fmu", metavar="FILE.fmu",
                   help="the FMU file to write (default: pdbfs.fmu in the current folder)")
    s.add_argument("--fmi-version", default="2", metavar="{2,3}", help="FMI version (default: 2)")
    s.add_argument("--platforms", default=None, metavar="P1,P2",
                   help="binaries to build: x86_64-linux, aarch64-linux, x86_64-windows, x86_64-darwin, "
                   "aarch64-darwin or all (linux64, win64 are aliases; default: this machine's)")
    s.add_argument("--author", default=None, help="the model's author (default: none stated)")
    s.add_argument("--license", default=None, help="the model's licence (default: pdbfs's, BSD-3-Clause); "
                   "pdbfs's C wrapper's and the embedded CVODES's BSD-3-Clause are added")
    s.add_argument("--copyright", default=None, help="the model's copyright notice (default: pdbfs's); "
                   "pdbfs's and CVODES's are added")
    s.set_defaults(func=cmd_export_fmu)
