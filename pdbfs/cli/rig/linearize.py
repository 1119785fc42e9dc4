"""pdbfs linearize: a rig's state-space matrices A, B, C, D at an operating
point, with the names of their rows and columns, as JSON (stdout or a
file), NumPy's .npz or MATLAB's .mat."""
from __future__ import annotations

import json
from pathlib import Path

from pdbfs.errors import ParameterError
from pdbfs.files import whole

from ..common import add_rig_options, check_output_file, parse_sets, rig_by_name
from .modes import add_initial_option, parse_at, parse_initial

FORMATS = (".json", ".npz", ".mat")


def names_of(text, option):
    """Comma-separated names, or None (the default) for no text."""
    if text is None:
        return None
    names = [n.strip() for n in text.split(",") if n.strip()]
    if not names:
        raise ParameterError(f"{option} {text!r}: give names, comma-separated")
    twice = next((n for k, n in enumerate(names) if n in names[:k]), None)
    if twice is not None:          # a row (column) twice would be no second output (input)
        raise ParameterError(f"{option} {text!r}: {twice} is listed twice")
    return names


def as_dict(lin, rig_name) -> dict:
    """The linearization as JSON-ready data (matrices as lists of rows)."""
    return {"rig": rig_name, "t": lin.t, "states": list(lin.states), "inputs": list(lin.inputs),
            "outputs": list(lin.outputs), "A": lin.A.tolist(), "B": lin.B.tolist(),
            "C": lin.C.tolist(), "D": lin.D.tolist(), "point": dict(lin.point),
            "units": dict(lin.units), "kinks": [k.to_dict() for k in lin.kinks]}


def write(path: Path, lin, rig_name):
    """``path`` by its extension, whole or not at all."""
    data = as_dict(lin, rig_name)
    with whole(path) as part:
        if path.suffix == ".json":
            part.write_text(json.dumps(data, allow_nan=False, indent=1) + "\n")
            return
        import numpy as np
        arrays = {k: np.asarray(getattr(lin, k), float) for k in "ABCD"}
        names = {k: np.array(data[k], dtype=object if path.suffix == ".mat" else str)
                 for k in ("states", "inputs", "outputs")}
        with open(part, "wb") as fh:
            if path.suffix == ".npz":
                np.savez(fh, **arrays, **names, t=np.float64(lin.t))
            else:
                from scipy.io import savemat
                savemat(fh, {**arrays, **names, "t": float(lin.t), "rig": rig_name})


def cmd_linearize(args):
    """pdbfs linearize: A, B, C, D with their names, as JSON or a .npz/.mat file."""
    out = None
    if args.out is not None:
        out = check_output_file(args.out, "--out")
        if out.suffix not in FORMATS:
            raise ParameterError(f"--out {args.out}: write .json, .npz or .mat (by the file's "
                                 "extension)")
    rig = rig_by_name(args.rig)
    params = parse_sets(args.set)
    lin = rig.linearize(parse_at(args.at), inputs=names_of(args.inputs, "--inputs"),
                        outputs=names_of(args.outputs, "--outputs"), params=params,
                        initial=parse_initial(args.initial))
    name = rig.compile().name
    if out is None:
        print(json.dumps(as_dict(lin, name), allow_nan=False))
        return
    write(out, lin, name)
    print(f"wrote {out}: A {lin.A.shape[0]}x{lin.A.shape[1]}, B with {len(lin.inputs)} "
          f"input(s), C with {len(lin.outputs)} output(s), at t = {lin.t:g} s")


def add_parsers(sub):
    """Add the ``linearize`` command to the subparsers ``sub``."""
    s = sub.add_parser("linearize", help="state-space matrices A, B, C, D of a rig, with names")
    add_rig_options(s)
    s.add_argument("--at", default="start", help="operating point: start, steady, or a time "
                   "of a run in s (default: start)")
    add_initial_option(s)
    s.add_argument("--inputs", default=None, metavar="NAME,...",
                   help="columns of B and D: the rig's inputs (held at their start values "
                   "at the point) or parameters (default: none)")
    s.add_argument("--outputs", default=None, metavar="NAME,...",
                   help="rows of C and D: variables of the rig (default: its outputs)")
    s.add_argument("--out", default=None, metavar="FILE",
                   help="write .json, .npz or .mat (default: JSON on stdout)")
    s.set_defaults(func=cmd_linearize)
