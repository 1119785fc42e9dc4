"""Plotly figures of the page as plain dicts (built in well under a
millisecond; plotly.graph_objects' validation would cost more than the run):
the pulse with its pins, trace and fits, and the design map."""
from __future__ import annotations

import base64

import numpy as np

from .numbers import shown_unit
from .traces import decimate

#: most points of a curve sent to the browser (the drop rig's 30001 would cost
#: a megabyte and a second of drawing per edit)
DRAWN = 6000

PIN_COLOURS = ("#7f7f7f", "#bcbd22", "#17becf", "#8c564b", "#e377c2")
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd")


def typed(a) -> dict:
    """A curve as Plotly's typed array (float32, base64): a quarter of the
    text, and nothing for the browser to parse; 7 digits are more than a
    screen shows."""
    a = np.ascontiguousarray(a, dtype="<f4")
    return {"dtype": "f4", "bdata": base64.b64encode(a.tobytes()).decode()}


def _scale(unit):
    return shown_unit(unit)


def legend_text(label: str, unit: str) -> str:
    """A curve's legend entry: its description and the unit it is drawn in."""
    shown = _scale(unit)[1]
    return f"{label} [{shown}]" if shown else label


def pulse_figure(curves: dict, pins=(), overlays=(), title="", labels=None) -> dict:
    """``curves``: {"t": seconds, name: (values, unit)} of the current run, one
    panel per unit (pressure, force, displacement), each curve named in the
    legend by ``labels[name]`` (its description) and its unit; ``pins``:
    (label, curves) drawn dashed, one legend entry per pin; ``overlays``:
    (label, t, y, unit) drawn on the panel of their unit (a measured trace,
    a fit). Hovering shows each value to 5 digits with its unit. ``title``
    (the rig) is kept in the layout's ``meta``."""
    labels = labels or {}
    units = []
    for name, (_, unit) in ((n, v) for n, v in curves.items() if n != "t"):
        if unit not in units:
            units.append(unit)
    rows = len(units) or 1
    gap = 0.04
    height = (1.0 - gap * (rows - 1)) / rows
    # the legend in rows above the panels, as wide as they are (beside them it
    # took a third of the width at 1280 px); the tool bar upright at the right
    layout = {"height": 190 * rows + 100, "margin": {"l": 70, "r": 36, "t": 30, "b": 45},
              "hovermode": "x", "uirevision": "pulse", "modebar": {"orientation": "v"},
              "showlegend": True,              # also for a rig of one curve: it says what it is
              "meta": {"rig": title},
              "legend": {"font": {"size": 11}, "orientation": "h", "x": 0, "xanchor": "left",
                         "y": 1.0, "yanchor": "bottom"}}
    data = []
    for k, unit in enumerate(units):
        axis = "" if k == 0 else str(k + 1)
        top = 1.0 - k * (height + gap)
        layout[f"yaxis{axis}"] = {"domain": [top - height, top], "title": {"text": _scale(unit)[1]},
                                  "anchor": f"x{axis}", "exponentformat": "power", "nticks": 6}
        layout[f"xaxis{axis}"] = {"anchor": f"y{axis}", "matches": "x" if k else None,
                                  "showticklabels": k == rows - 1, "hoverformat": ".5~g",
                                  "title": {"text": "time [ms]"} if k == rows - 1 else None}
    where = {unit: ("" if k == 0 else str(k + 1)) for k, unit in enumerate(units)}

    def add(t, y, unit, name, hover, **style):
        if unit not in where:
            return
        f, shown = _scale(unit)
        ax = where[unit]
        t, y = decimate(t, y, DRAWN)             # a screen's width of points, peaks kept
        hover = hover.replace("<", "&lt;")
        data.append({"type": "scattergl" if len(t) > 5000 else "scatter", "mode": "lines",
                     "x": typed(np.asarray(t, float) * 1e3), "y": typed(np.asarray(y, float) * f),
                     "name": name, "hovertemplate": f"%{{y:.5~g}} {shown}<extra>{hover}</extra>",
                     "xaxis": f"x{ax}", "yaxis": f"y{ax}", **style})

    for j, (label, pin) in enumerate(pins):
        colour = PIN_COLOURS[j % len(PIN_COLOURS)]
        for k, (name, (y, unit)) in enumerate((n, v) for n, v in pin.items() if n != "t"):
            add(pin["t"], y, unit, label, f"{label}: {labels.get(name, name)}",
                line={"dash": "dash", "color": colour, "width": 1.2}, legendgroup=label,
                showlegend=k == 0)
    for j, (name, (y, unit)) in enumerate((n, v) for n, v in curves.items() if n != "t"):
        text = legend_text(labels.get(name, name), unit)
        add(curves["t"], y, unit, text, text,
            line={"color": COLOURS[j % len(COLOURS)], "width": 2})
    for j, (label, t, y, unit) in enumerate(overlays):
        style = {"mode": "markers", "marker": {"size": 4, "color": "black"}} if j == 0 and \
            label.startswith("trace") else {"line": {"color": "#e6550d", "dash": "dot"}}
        add(t, y, unit, legend_text(label, unit), label, **style)
    return {"data": data, "layout": layout}


def map_figure(m: dict) -> dict:
    """Peak pressure (colour) and pulse duration (white contours) over two
    settings, the axes named by ``x_label``/``y_label`` (a parameter's name
    and description) and unit."""
    x, y = m["x"], m["y"]
    peak = np.array(m["values"]["peak_pressure"], float) * 1e-6
    dur = np.array(m["values"]["pulse_duration"], float) * 1e3

    def grid(z):
        return [[None if not np.isfinite(v) else float(v) for v in row] for row in z]

    def log(v):
        v = np.asarray(v, float)
        return bool(np.all(v > 0) and len(v) > 2 and abs((v[2] / v[1]) - (v[1] / v[0])) < 1e-9
                    and abs((v[2] - v[1]) - (v[1] - v[0])) > 1e-12 * abs(v[1]))

    def title(axis):
        name, unit = m.get(f"{axis}_label") or m[f"{axis}_name"], m.get(f"{axis}_unit")
        return f"{name} [{unit}]" if unit and unit != "1" else name

    def unit(axis):
        u = m.get(f"{axis}_unit")
        return f" {u}" if u and u != "1" else ""

    where = (f"{m['x_name']} %{{x:.4~g}}{unit('x')}<br>{m['y_name']} %{{y:.4~g}}{unit('y')}<br>")
    data = [{"type": "contour", "x": x, "y": y, "z": grid(peak), "colorscale": "Viridis",
             "colorbar": {"title": {"text": "peak pressure [MPa]"}}, "name": "peak pressure",
             "contours": {"coloring": "heatmap"},
             "hovertemplate": where + "peak pressure %{z:.5~g} MPa<extra></extra>"},
            {"type": "contour", "x": x, "y": y, "z": grid(dur), "showscale": False,
             "contours": {"coloring": "none", "showlabels": True, "labelformat": ".3~g",
                          "labelfont": {"color": "white"}},
             "hovertemplate": where + "pulse duration %{z:.5~g} ms<extra></extra>",
             "line": {"color": "white"}, "name": "pulse duration [ms]"}]
    return {"data": data, "layout": {
        "height": 480, "margin": {"l": 80, "r": 20, "t": 40, "b": 50},
        "title": {"text": "peak pressure (colour, MPa) and pulse duration (white lines, ms)",
                  "font": {"size": 13}},
        # 2.2e8, never Plotly's default 0.22B
        "xaxis": {"title": {"text": title("x")}, "type": "log" if log(x) else "linear",
                  "exponentformat": "power", "hoverformat": ".4~g"},
        "yaxis": {"title": {"text": title("y")}, "type": "log" if log(y) else "linear",
                  "exponentformat": "power", "hoverformat": ".4~g"}}}
