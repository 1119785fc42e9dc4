"""pdbfs example-data: the example files shipped with pdbfs (a measured-like
trace to calibrate to, a target pulse to design for, a gun firing to compare
blows with), listed or copied to a folder."""
from __future__ import annotations

import shutil

from pdbfs.errors import ParameterError
from pdbfs.files import EXAMPLES, example_data, whole

from .common import prepare_out


def cmd_example_data(args):
    """pdbfs example-data: list the example files, or copy them into --out."""
    if args.out is None:                 # nothing written: what there is, and where
        for name, what in EXAMPLES.items():
            print(f"{name:<24} {what}")
            print(f"{'':<24} {example_data(name)}")
        print("copy them to a folder with: pdbfs example-data --out DIR")
        return 0
    out = prepare_out(args.out)
    todo, same = [], []
    for name in EXAMPLES:                # every clash refused before anything is copied
        src, dest = example_data(name), out / name
        if dest.is_dir():
            raise ParameterError(f"--out {args.out}: {dest} is a folder")
        if dest.exists() and not args.force:
            if dest.read_bytes() == src.read_bytes():
                same.append(dest)
                continue
            raise ParameterError(f"--out {args.out}: {dest} exists and differs from the example; "
                                 "choose another folder, or --force to replace it")
        todo.append((src, dest))
    out.mkdir(parents=True, exist_ok=True)
    for src, dest in todo:
        with whole(dest) as part:
            shutil.copyfile(src, part)
    if todo:
        print("wrote " + ", ".join(str(d) for _, d in todo))
    if same:
        print("already there: " + ", ".join(str(d) for d in same))
    return 0


def add_parsers(sub):
    """Add the ``example-data`` command to the subparsers ``sub``."""
    s = sub.add_parser("example-data", help="list the example files shipped with pdbfs, or "
                       "copy them to a folder (--out)",
                       description="The example files shipped with pdbfs: "
                       + "; ".join(f"{n}: {w}" for n, w in EXAMPLES.items())
                       + ". Without --out they are listed and nothing is written.")
    s.add_argument("--out", default=None, metavar="DIR",
                   help="folder to copy them to (made if need be; default: none, only list them)")
    s.add_argument("--force", action="store_true",
                   help="replace files of the same name in --out that differ from the examples "
                   "(default: refuse, and copy nothing)")
    s.set_defaults(func=cmd_example_data)
