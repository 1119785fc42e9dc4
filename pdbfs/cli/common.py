"""What every command shares: rig names, --set parsing, printing a summary."""
from __future__ import annotations

from pdbfs.errors import ParameterError


def rig_by_name(name):
    from pdbfs.models import RIGS
    if name not in RIGS:
        raise ParameterError(f"unknown rig {name!r}; choose one of {', '.join(RIGS)}")
    return RIGS[name]()


def parse_sets(items):
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


def print_summary(summary):
    from pdbfs.simulation import SUMMARY_UNITS as UNITS
    for k, v in summary.items():
        if isinstance(v, (list, tuple)):   # one value per blow (rigs with repeated impacts)
            vals = ", ".join(f"{x:.6g}" for x in v)
            print(f"  {k:<26} [{vals}] {UNITS.get(k, '')}")
        elif v is None:                    # not defined for this run (e.g. no contact)
            print(f"  {k:<26} {'n/a':>14}")
        else:
            print(f"  {k:<26} {v:>14.6g} {UNITS.get(k, '')}")
