"""pdbfs export-ssp: a system of FMUs, connected output to input, as an SSP
1.0 file (pdbfs.fmu.export_ssp); ``--example pulse-pid`` exports the
closed-loop pulse rig's plant and controller as FMUs and connects them."""
from __future__ import annotations

import tempfile
from pathlib import Path

from pdbfs.errors import ExportError

from ..common import check_output_file

#: the systems --example writes: name -> what it is
EXAMPLES = {"pulse-pid": "the closed-loop pulse rig: its plant (valve, chamber, pressure sensor) and its "
                         "PI controller, each an FMU, the pressure fed to the controller, its command "
                         "to the valve"}


def _pairs(items, option: str, sep: str) -> list[tuple[str, str]]:
    out = []
    for item in items or []:
        a, s, b = item.partition(sep)
        if not s or not a.strip() or not b.strip():
            raise ExportError(f"{option} {item!r}: give " + ("NAME=FILE.fmu" if sep == "=" else
                                                             "ELEMENT.OUTPUT:ELEMENT.INPUT"))
        out.append((a.strip(), b.strip()))
    return out


def _example(name: str, version: int, folder: Path) -> tuple[dict, tuple]:
    """The example's FMUs, exported into ``folder``, and its connections."""
    from pdbfs.models import LOOP, pulse_controller_rig, pulse_plant_rig
    if name not in EXAMPLES:
        raise ExportError(f"--example {name!r}: choose one of {', '.join(EXAMPLES)}")
    fmus = {}
    for element, build in (("plant", pulse_plant_rig), ("controller", pulse_controller_rig)):
        fmus[element] = build().export_fmu(folder / f"{element}.fmu", fmi_version=version)
    return fmus, LOOP


def cmd_export_ssp(args):
    """pdbfs export-ssp: write the system's SSP file."""
    from pdbfs.fmu import check_fmi_version, export_ssp
    from pdbfs.fmu.ssp import check_ssp_target
    check_output_file(args.output)
    check_ssp_target(args.output)
    fmus, links = _pairs(args.fmu, "--fmu", "="), _pairs(args.connect, "--connect", ":")
    if args.example and (fmus or links):
        raise ExportError("--example writes its own FMUs and connections: give it without --fmu and "
                          "--connect")
    if not args.example and not fmus:
        raise ExportError("give the FMUs (--fmu NAME=FILE.fmu, one per component) and their "
                          "connections (--connect ELEMENT.OUTPUT:ELEMENT.INPUT), or --example pulse-pid")
    names = [n for n, _ in fmus]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ExportError(f"--fmu: component {dup[0]} is given twice")
    if args.fmi_version is not None and not args.example:
        raise ExportError("--fmi-version chooses the version of --example's FMUs; the FMUs given with "
                          "--fmu are used as they are")
    given = args.fmi_version or "2"
    version = check_fmi_version(int(given) if given in ("2", "3") else given)
    with tempfile.TemporaryDirectory(prefix="pdbfs-ssp-") as tmp:
        if args.example:
            fmus, links = _example(args.example, version, Path(tmp))
        path = export_ssp(args.output, dict(fmus), links, name=args.name or args.example or "system",
                          stop_time=args.stop_time)
    print(f"wrote {path}")


def add_parsers(sub):
    """Add the ``export-ssp`` command to the subparsers ``sub``."""
    s = sub.add_parser(
        "export-ssp", help="write a system of FMUs connected output to input as an SSP 1.0 file",
        description="Write an SSP (System Structure and Parameterization 1.0) file: the FMUs given, "
        "stored in it, and the connections from their outputs to their inputs, for a co-simulation "
        "engine (Ecos, libcosim, OMSimulator, ...). Each connection joins an output to an input of "
        "the same unit; each input takes one output. --example pulse-pid exports the closed-loop "
        "pulse rig's plant and controller and connects them.")
    s.add_argument("-o", "--output", default="system.ssp", metavar="FILE.ssp",
                   help="the SSP file to write (default: system.ssp in the current folder)")
    s.add_argument("--fmu", action="append", metavar="NAME=FILE.fmu",
                   help="a component: its name in the system and its FMU (Co-Simulation, FMI 2.0 or "
                   "3.0); repeat for each")
    s.add_argument("--connect", action="append", metavar="ELEMENT.OUTPUT:ELEMENT.INPUT",
                   help="a connection, e.g. plant.sensor.y:controller.measured; repeat for each")
    s.add_argument("--example", default=None, choices=list(EXAMPLES),
                   help="write an example system instead: " + "; ".join(f"{k}, {v}" for k, v in
                                                                       EXAMPLES.items()))
    s.add_argument("--fmi-version", default=None, metavar="{2,3}",
                   help="FMI version of the example's FMUs (default: 2)")
    s.add_argument("--name", default=None, help="the system's name (default: the example's, else system)")
    s.add_argument("--stop-time", type=float, default=None, metavar="S",
                   help="the default experiment's stop time, s (default: the FMUs' shortest)")
    s.set_defaults(func=cmd_export_ssp)
