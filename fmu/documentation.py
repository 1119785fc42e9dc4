"""documentation/index.html of a pdbfs FMU (the place FMI gives for it):
the rig, every parameter with unit, range, tunability and description, the
outputs, the solver parameters, and how the FMU was built."""
from __future__ import annotations

import html
from importlib import metadata

from .rights import LICENSE_ENTRY, LICENSE_IN_FMU, PDBFS_LICENSE, PDBFS_LICENSE_IN_FMU
from .variables import SOLVER_METHODS, FmuModel


#: where each FMI version lists the C files of a source build
_LISTED = {2: "<code>modelDescription.xml</code>", 3: "<code>sources/buildDescription.xml</code>"}


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "unknown"


def _num(v) -> str:
    return "" if v is None else html.escape(f"{v:.6g}" if isinstance(v, float) else str(v))


def _table(head: list[str], rows: list[list[str]]) -> list[str]:
    out = ["<table>", "<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>"]
    out += ["<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows]
    return out + ["</table>"]


def _range(v) -> str:
    if v.type == "Enumeration":   # solver.method: its items, as the type declares them
        return ", ".join(f"{v} ({html.escape(n)})" for n, v, _ in SOLVER_METHODS)
    lo = "-&infin;" if v.min is None else _num(v.min)
    hi = "&infin;" if v.max is None else _num(v.max)
    return f"[{lo}, {hi}]"


def index_html(model: FmuModel, platforms: list[str], sundials_version: str, casadi_version: str,
               has_sources: bool, fmi_version: int = 2, license: str | None = None) -> str:
    """The HTML page of ``model``'s FMU, built for ``platforms``; ``license``:
    the model's licence as its user stated it (None: pdbfs's, BSD-3-Clause)."""
    d = model.dae
    e = html.escape
    param_names = set(d.p_names)
    solver = [v for v in model.vars if v.name.startswith("solver.")]
    params = [v for v in model.vars if v.name in param_names]
    positive = {p.name for p in d.params if p.positive}
    calc = [v for v in model.vars if v.causality == "calculatedParameter"]
    outputs = [v for v in model.vars if v.causality == "output"]
    states = [model.vars[i - 1] for i in model.x_index]
    L = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
         f"<title>{e(model.ident)}: pdbfs FMU of rig {e(d.name)}</title>",
         "<style>body{font-family:sans-serif;max-width:70em;margin:auto}"
         "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 6px;text-align:left}"
         "</style></head><body>",
         f"<h1>Rig <code>{e(d.name)}</code></h1>",
         f"<p>{e(getattr(d, 'description', '') or 'A rig built with pdbfs.')}</p>",
         f"<p>An FMI {fmi_version}.0 FMU (Model Exchange and Co-Simulation) exported by pdbfs: a lumped model, "
         f"{model.nx} states, {model.npar} parameters, {model.nu} inputs, {model.ne} event indicators "
         "(below). Units are SI. "
         "In Co-Simulation the FMU integrates with CVODE (SUNDIALS) or an explicit Runge-Kutta "
         "method 8(5,3) inside (<code>solver.method</code>; <em>auto</em>, the default, takes the "
         "explicit method where the rig is not stiff over the run), through the event "
         "indicators' roots; results do not depend on the communication step.</p>",
         "<h2>Parameters</h2>",
         "<p>Tunable parameters may be changed between communication steps (Co-Simulation) or in event "
         "mode (Model Exchange); fixed ones only before initialisation. A range is inclusive; a "
         "parameter marked <em>&gt; 0</em> must be strictly positive, which FMI's inclusive "
         "<code>min</code> cannot say: its declared <code>min</code> is the smallest normal double "
         "(2.2e-308), and 0 is refused.</p>"]
    L += _table(["name", "unit", "default", "range", "tunability", "description"],
                [[f"<code>{e(v.name)}</code>", e(v.unit or ""), _num(v.start), _range(v)
                  + (" <em>&gt; 0</em>" if v.name in positive else ""), v.variability, e(v.description)]
                 for v in params])
    if calc:
        L += ["<h2>Calculated parameters</h2>"]
        L += _table(["name", "unit", "description"],
                    [[f"<code>{e(v.name)}</code>", e(v.unit or ""), e(v.description)] for v in calc])
    inputs = [v for v in model.vars if v.causality == "input"]
    if inputs:
        L += ["<h2>Inputs</h2>",
              "<p>Set by the importer at any time; Co-Simulation holds each from the communication point "
              "where it is set, or (FMI 2.0, <code>fmi2SetRealInputDerivatives</code>, first order) runs it "
              "linearly from there with the slope given. A changed input restarts the solver. Model "
              "Exchange reads the value set.</p>"]
        L += _table(["name", "unit", "start", "description"],
                    [[f"<code>{e(v.name)}</code>", e(v.unit or ""), _num(v.start), e(v.description)]
                     for v in inputs])
    L += ["<h2>Outputs</h2>"]
    L += _table(["name", "unit", "description"],
                [[f"<code>{e(v.name)}</code>", e(v.unit or ""), e(v.description)] for v in outputs])
    L += ["<h2>States</h2>"]
    L += _table(["name", "unit", "nominal", "description"],
                [[f"<code>{e(v.name)}</code>", e(v.unit or ""), _num(v.nominal), e(v.description)]
                 for v in states])
    if model.ne:
        L += ["<h2>Event indicators</h2>", "<p>Each changes sign where the right-hand side switches:</p>"]
        L += _table(["name", "marks"], [[f"<code>{e(n)}</code>", e(getattr(d, "event_text", {}).get(n, ""))]
                                        for n in d.event_names])
    L += ["<h2>Solver parameters (Co-Simulation)</h2>"]
    L += _table(["name", "unit", "default", "range", "description"],
                [[f"<code>{e(v.name)}</code>", e(v.unit or ""), _num(v.start), _range(v), e(v.description)]
                 for v in solver])
    L += [f"<p>Default experiment: 0 to {model.stop_time:g} s, step {model.step_size:g} s, "
          f"tolerance {model.tolerance:g}.</p>",
          "<h2>How it was built</h2>", "<ul>",
          f"<li>pdbfs {e(_version('pdbfs'))}; model C generated by CasADi {e(casadi_version)}</li>",
          f"<li>binaries: {e(', '.join(platforms))} (each linked with a static CVODE of SUNDIALS "
          f"{e(sundials_version)}, all built by zig cc -O2)</li>",
          ("<li>sources: <code>sources/</code> builds the binary with a plain C compiler, SUNDIALS' "
           f"CVODE sources included, listed in {_LISTED[fmi_version]}; see <code>sources/README.txt</code></li>") if has_sources else
          "<li>sources: the FMU's own C files only (SUNDIALS' sources were not available)</li>",
          f"<li>licences (<code>{LICENSE_ENTRY}</code>): the model "
          + (f"{e(license)}" if license is not None else f"{PDBFS_LICENSE}, as pdbfs")
          + f"; pdbfs's C wrapper {PDBFS_LICENSE} (<code>{PDBFS_LICENSE_IN_FMU}</code>); SUNDIALS' CVODES "
          + "BSD-3-Clause" + (f" (<code>{LICENSE_IN_FMU}</code>)" if has_sources else "") + "</li>",
          "</ul></body></html>", ""]
    return "\n".join(L)
