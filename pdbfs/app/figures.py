"""Plotly figures of the page as plain dicts (built in well under a
millisecond; plotly.graph_objects' validation would cost more than the run):
the pulse with its pins, trace and fits, and the design map."""
from __future__ import annotations

import base64

import numpy as np

from .traces import decimate

#: most points of a curve sent to the browser (the drop rig's 30001 would cost
#: a megabyte and a second of drawing per edit)
DRAWN = 6000

#: display scale of SI units: (factor, label)
SCALE = {"Pa": (1e-6, "MPa"), "N": (1e-3, "kN"), "m": (1e3, "mm"), "s": (1e3, "ms")}
PIN_COLOURS = ("#7f7f7f", "#bcbd22", "#17becf", "#8c564b", "#e377c2")
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd")


def typed(a) -> dict:
    """A curve as Plotly's typed array (float32, base64): a quarter of the
    text, and nothing for the browser to parse; 7 digits are more than a
    screen shows."""
    a = np.ascontiguousarray(a, dtype="<f4")
    return {"dtype": "f4", "bdata": base64.b64encode(a.tobytes()).decode()}


def _scale(unit):
    return SCALE.get(unit, (1.0, unit))


def pulse_figure(curves: dict, pins=(), overlays=(), title="") -> dict:
    """``curves``: {"t": seconds, name: (values, unit)} of the current run, one
    panel per unit (pressure, force, displacement); ``pins``: (label, curves)
    drawn dashed; ``overlays``: (label, t, y, unit) drawn on the panel of their
    unit (a measured trace, a fit)."""
    units = []
    for name, (_, unit) in ((n, v) for n, v in curves.items() if n != "t"):
        if unit not in units:
            units.append(unit)
    rows = len(units) or 1
    gap = 0.04
    height = (1.0 - gap * (rows - 1)) / rows
    layout = {"height": 190 * rows + 80, "margin": {"l": 70, "r": 20, "t": 36, "b": 45},
              "title": {"text": title, "font": {"size": 13}}, "hovermode": "x",
              "legend": {"font": {"size": 10}}, "uirevision": "pulse"}
    data = []
    for k, unit in enumerate(units):
        axis = "" if k == 0 else str(k + 1)
        top = 1.0 - k * (height + gap)
        layout[f"yaxis{axis}"] = {"domain": [top - height, top], "title": {"text": _scale(unit)[1]},
                                  "anchor": f"x{axis}"}
        layout[f"xaxis{axis}"] = {"anchor": f"y{axis}", "matches": "x" if k else None,
                                  "showticklabels": k == rows - 1,
                                  "title": {"text": "time (ms)"} if k == rows - 1 else None}
    where = {unit: ("" if k == 0 else str(k + 1)) for k, unit in enumerate(units)}

    def add(t, y, unit, name, **style):
        if unit not in where:
            return
        f, _ = _scale(unit)
        ax = where[unit]
        t, y = decimate(t, y, DRAWN)             # a screen's width of points, peaks kept
        data.append({"type": "scattergl" if len(t) > 5000 else "scatter", "mode": "lines",
                     "x": typed(np.asarray(t, float) * 1e3), "y": typed(np.asarray(y, float) * f),
                     "name": name,
                     "xaxis": f"x{ax}", "yaxis": f"y{ax}", **style})

    for j, (label, pin) in enumerate(pins):
        colour = PIN_COLOURS[j % len(PIN_COLOURS)]
        for name, (y, unit) in ((n, v) for n, v in pin.items() if n != "t"):
            add(pin["t"], y, unit, f"{label}: {name}", line={"dash": "dash", "color": colour,
                                                               "width": 1.2}, legendgroup=label)
    for j, (name, (y, unit)) in enumerate((n, v) for n, v in curves.items() if n != "t"):
        add(curves["t"], y, unit, name, line={"color": COLOURS[j % len(COLOURS)], "width": 2})
    for j, (label, t, y, unit) in enumerate(overlays):
        style = {"mode": "markers", "marker": {"size": 4, "color": "black"}} if j == 0 and \
            label.startswith("trace") else {"line": {"color": "#e6550d", "dash": "dot"}}
        add(t, y, unit, label, **style)
    return {"data": data, "layout": layout}


def map_figure(m: dict) -> dict:
    """Peak pressure (colour) and pulse duration (white contours) over two settings."""
    x, y = m["x"], m["y"]
    peak = np.array(m["values"]["peak_pressure"], float) * 1e-6
    dur = np.array(m["values"]["pulse_duration"], float) * 1e3

    def grid(z):
        return [[None if not np.isfinite(v) else float(v) for v in row] for row in z]

    def log(v):
        v = np.asarray(v, float)
        return bool(np.all(v > 0) and len(v) > 2 and abs((v[2] / v[1]) - (v[1] / v[0])) < 1e-9
                    and abs((v[2] - v[1]) - (v[1] - v[0])) > 1e-12 * abs(v[1]))

    data = [{"type": "contour", "x": x, "y": y, "z": grid(peak), "colorscale": "Viridis",
             "colorbar": {"title": {"text": "peak (MPa)"}}, "name": "peak pressure",
             "contours": {"coloring": "heatmap"}},
            {"type": "contour", "x": x, "y": y, "z": grid(dur), "showscale": False,
             "contours": {"coloring": "none", "showlabels": True,
                          "labelfont": {"color": "white"}},
             "line": {"color": "white"}, "name": "duration (ms)"}]
    xl = f"{m['x_name']} ({m['x_unit']})" if m.get("x_unit") else m["x_name"]
    yl = f"{m['y_name']} ({m['y_unit']})" if m.get("y_unit") else m["y_name"]
    return {"data": data, "layout": {
        "height": 480, "margin": {"l": 80, "r": 20, "t": 40, "b": 50},
        "title": {"text": "peak pressure (colour) and pulse duration (white, ms)", "font": {"size": 13}},
        "xaxis": {"title": {"text": xl}, "type": "log" if log(x) else "linear"},
        "yaxis": {"title": {"text": yl}, "type": "log" if log(y) else "linear"}}}
