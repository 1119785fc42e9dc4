"""How pdbfs's objects show themselves in a console and a notebook: one
readable line (``__repr__``) and a small HTML table (``_repr_html_``), built
by the same few functions for Rig, Result, SweepResult, Calibration and
Design. Numbers are printed to six significant digits with their units."""
from __future__ import annotations


def number(value, unit: str = "") -> str:
    """``value`` as a person reads it: 6 significant digits, then the unit."""
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    try:
        text = f"{float(value):.6g}"
    except (TypeError, ValueError):
        return str(value)
    return f"{text} {unit}".rstrip() if unit and unit != "1" else text


def values(params: dict, units: dict | None = None) -> str:
    """``name value unit, ...`` of a dict of numbers."""
    units = units or {}
    return ", ".join(f"{k} {number(v, units.get(k, ''))}" for k, v in params.items())


def table(title: str, rows: list[tuple[str, str]]) -> str:
    """An HTML table of (label, text) rows under a bold title."""
    import html          # (notebooks only: not on every import of pdbfs)
    body = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
                   f"<td style='text-align:left'>{html.escape(v)}</td></tr>" for k, v in rows)
    return f"<div><b>{html.escape(title)}</b><table>{body}</table></div>"
