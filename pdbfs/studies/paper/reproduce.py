"""The paper's figures, regenerated (``pdbfs reproduce``).

Cho & Cha (2010), Figs. 4-9, with the paper's axes, ranges and legends, from
the rig in ``pdbfs.models.paper`` (Table 1 values, the oil column read as a
linear spring and Table 1's D, as the documentation's page on it explains), plus the
figures of the variant rigs: the force front through a split piston, the
contact under each damping law, and the drop-height rig's repeated blows.

    from pdbfs.studies.paper import reproduce
    out = reproduce("paper-figures")     # {figure name: path}, table rows

Every curve's peak pressure, time of peak and pulse duration go to
``table.csv`` (and ``table.md``) beside the figures.
"""
from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

from pdbfs.errors import ParameterError

from .cases import FIGURES, N_PER_MS, T_TABLE
from .figures import BUILDERS


@dataclass
class Reproduction:
    """What ``reproduce`` wrote: figure paths by name, and the table."""

    out: Path
    figures: dict = field(default_factory=dict)
    table: list = field(default_factory=list)      # dicts: figure, curve, peaks
    notes: dict = field(default_factory=dict)      # numbers quoted in the docs


def reproduce(out="paper-figures", *, figures=None, fast=False, progress=False) -> Reproduction:
    """Write the paper's Figs. 4-9 and the variant figures as PNGs into
    ``out``, and ``table.csv`` / ``table.md`` of every curve's peak pressure,
    time of peak and pulse duration. ``figures`` picks a subset of
    ``FIGURES`` (by full name or prefix, e.g. ["fig4", "fig6"]); ``fast``
    uses a coarser output grid (tests)."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    wanted = _select(figures)
    rep = Reproduction(out=out)
    ctx = _Context(fast=fast, progress=progress)
    for name in wanted:
        path = out / f"{name}.png"
        BUILDERS[name](ctx, rep, path)
        rep.figures[name] = path
    _write_table(rep)
    return rep


def _select(figures):
    if figures is None:
        return list(FIGURES)
    chosen = []
    for f in figures:
        hits = [n for n in FIGURES if n == f or n.startswith(f)]
        if not hits:
            raise ParameterError(f"reproduce: unknown figure {f!r}; choose from {', '.join(FIGURES)}")
        chosen += [h for h in hits if h not in chosen]
    return chosen


class _Context:
    def __init__(self, fast, progress):
        from pdbfs.models import paper_rig
        self.fast = fast
        self.progress = progress
        self.rig = paper_rig()
        self.per_ms = 40 if fast else N_PER_MS

    def n_out(self, t_end):
        return int(round(t_end * 1e3 * self.per_ms)) + 1

    def study(self, name, values, t_end=T_TABLE):
        """Sweep one parameter of the paper rig; keep the trajectories."""
        from pdbfs.studies.sweeps import sweep
        return sweep(self.rig, {name: values}, t_end=t_end, n_out=self.n_out(t_end),
                     trajectories=True, progress=self.progress)




# ------------------------------------------------------------------ table
COLUMNS = ("figure", "curve", "peak_pressure_MPa", "time_of_peak_ms", "pulse_duration_ms",
           "peak_contact_force_MN", "max_piston_displacement_mm")


def _write_table(rep):
    with open(rep.out / "table.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, COLUMNS)
        w.writeheader()
        for row in rep.table:
            w.writerow({k: row.get(k, "") for k in COLUMNS})
    head = ("| figure | curve | peak pressure (MPa) | time of peak (ms) | pulse duration (ms) |",
            "|---|---|---:|---:|---:|")
    lines = list(head)
    for r in rep.table:
        cells = [r["figure"], r["curve"]] + [
            f"{r[k]:.2f}" if k in r else "" for k in
            ("peak_pressure_MPa", "time_of_peak_ms", "pulse_duration_ms")]
        lines.append("| " + " | ".join(cells) + " |")
    (rep.out / "table.md").write_text("\n".join(lines) + "\n")
