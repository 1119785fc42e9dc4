"""pdbfs rigs: the rigs --rig names, each with its description and its
inputs (and, as JSON, its outputs)."""
from __future__ import annotations

import json

from ..common import rig_by_name


def rig_entry(name: str) -> dict:
    """One rig as JSON-ready data: name, description, inputs, outputs, sizes."""
    from pdbfs.models import rig_description
    rig = rig_by_name(name)
    dae = rig.compile()
    return {"name": name, "rig": dae.name, "class": type(rig).__name__,
            "description": rig_description(name, rig),
            "inputs": [{"name": u.name, "unit": u.unit, "description": u.description,
                        "start": u.start} for u in dae.inputs],
            "outputs": [{"name": v.name, "unit": v.unit, "description": v.description}
                        for v in dae.y_info if v.output],
            "signals": dict(getattr(dae, "signals", {}) or {}),
            "parameters": len(dae.params), "states": int(dae.x.numel())}


def cmd_rigs(args):
    """pdbfs rigs: list the shipped rigs (or the one --rig names) with their inputs."""
    from pdbfs.models import RIGS
    names = [args.rig] if args.rig is not None else list(RIGS)
    entries = [rig_entry(n) for n in names]
    if args.json:
        print(json.dumps(entries, allow_nan=False))
        return
    for e in entries:
        print(f"{e['name']}: {e['description']}")
        print(f"    {e['states']} states, {e['parameters']} parameters; "
              + ("inputs:" if e["inputs"] else "no inputs"))
        for u in e["inputs"]:
            print(f"      {u['name']} [{u['unit']}] {u['description']} (start {u['start']:g})")
    if args.rig is None:
        print("Any command takes a rig of your own as --rig FILE.py:NAME or MODULE:NAME. "
              "`pdbfs params --rig RIG` lists a rig's parameters; `pdbfs rigs --json`, its outputs.")


def add_parsers(sub):
    """Add the ``rigs`` command to the subparsers ``sub``."""
    s = sub.add_parser("rigs", help="list the rigs --rig names, with their descriptions and inputs")
    s.add_argument("--rig", default=None, metavar="RIG",
                   help="describe this rig only (a name, or FILE.py:NAME / MODULE:NAME of your own; "
                   "default: every rig pdbfs ships)")
    s.add_argument("--json", action="store_true",
                   help="print each rig's name, description, inputs (name, unit, description, start), "
                   "outputs (name, unit, description), summary signals and sizes as JSON")
    s.set_defaults(func=cmd_rigs)
