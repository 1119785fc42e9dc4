"""The page's quick callbacks (each a millisecond or so of work): settings
edited by a field, a slider, reset or apply; the run and its summary; pins;
the uploaded trace; the small downloads. A PdbfsError is shown next to what
caused it, never raised: the server does not die of bad input."""
from __future__ import annotations

import json
import math
import re

from dash import ALL, Input, Output, State, ctx, dcc, html, no_update
from dash.exceptions import PreventUpdate

from pdbfs.errors import PdbfsError

from . import traces
from .figures import pulse_figure
from .numbers import quantity
from .page import (controls, field_text, fmt, free_options, initial_settings, marks, parts_toggle,
                   study_defaults)
from .workbench import workbench

MAX_PINS = 5
LABELS = {"peak_pressure": "peak pressure", "time_of_peak": "time of peak",
          "pulse_duration": "pulse duration", "complete": "complete",
          "peak_contact_force": "peak contact force",
          "max_piston_displacement": "max. piston displacement",
          "restitution_coefficient": "restitution", "impact_count": "blows",
          "impact_times": "times of the blows", "impact_peak_pressures": "peaks of the blows",
          "impact_durations": "durations of the blows"}


def _apply(wb, values, changes):
    """Settings with ``changes`` (the fitted or designed values; a drop height
    brings its impact speed, and an impact speed its drop height)."""
    values = dict(values)
    for name, v in changes.items():
        if v is None or name not in values:
            continue
        values.update(wb.check(name, v))
    return values


def edit_settings(slider_vals, field_vals, _reset, _cal, _des, settings, cal, des, msgs, pins,
                  trace):
    """A field, a slider, reset or apply changed the settings: the controls that
    follow, the messages, and the new run drawn, all in one answer (one
    round trip per slider step)."""
    wb = workbench(settings["rig"])
    shown = wb.shown(settings.get("parts", False))
    names = [c.name for c in shown]
    sliders = [s["id"]["name"] for s in ctx.inputs_list[0]]
    if sliders != names:                  # the controls of another rig are being drawn
        raise PreventUpdate
    values = dict(settings["values"])
    msgs = list(msgs)
    trig = ctx.triggered_id
    changed, texts = {}, {}
    if trig == "reset":
        changed = wb.defaults()
        msgs = [None] * len(names)
    elif trig in ("cal-apply", "des-apply"):
        result = cal if trig == "cal-apply" else des
        if not result:
            raise PreventUpdate
        try:
            new = _apply(wb, values, result["params"])
        except PdbfsError:
            raise PreventUpdate from None
        changed = {k: v for k, v in new.items() if v != values[k]}
    elif isinstance(trig, dict):
        name = trig["name"]
        k = names.index(name)
        c = shown[k]
        if trig["type"] == "slider":
            s = slider_vals[k]
            if s is None or abs(s - c.to_slider(values[name])) < c.step / 2:
                raise PreventUpdate           # a slider settling on its step: not a change
            text = field_text(c, c.slider_value(s))
            texts[name] = text
        else:
            text = field_vals[k]
        try:
            changed = wb.check(name, text)
            msgs[k] = None
        except PdbfsError as err:
            msgs[k] = str(err)
            keep = [no_update] * len(names)
            return (keep, keep, keep, keep, keep, msgs, no_update) + (no_update,) * 3
    else:
        raise PreventUpdate
    values.update(changed)
    out_s, out_lo, out_hi, out_m, out_f = [], [], [], [], []
    for k, (c, name) in enumerate(zip(shown, names)):
        v = values[name]
        lo, hi = c.slider_range(v)
        moved = name in changed
        slider_moved = isinstance(trig, dict) and trig["type"] == "slider" and trig["name"] == name
        out_s.append(c.to_slider(v) if moved and not slider_moved else no_update)
        out_lo.append(lo if moved else no_update)
        out_hi.append(hi if moved else no_update)
        out_m.append(marks(c, lo, hi) if moved else no_update)
        field_typed = isinstance(trig, dict) and trig["type"] == "field" and trig["name"] == name
        # a value that follows the one edited (an impact speed, its drop height) to 4 digits
        follows = isinstance(trig, dict) and trig["name"] != name
        out_f.append(texts.get(name, field_text(c, v, follows)) if moved and not field_typed
                     else no_update)
        if moved and msgs[k] and not field_typed:
            msgs[k] = None
    settings = {**settings, "values": values}
    return (out_s, out_lo, out_hi, out_m, out_f, msgs, settings) + draw(settings, pins, trace, cal, des)


def _summary_table(rows):
    trs = []
    for key, v, unit in rows:
        if isinstance(v, bool):
            text = "yes" if v else "no (cut off at the end of the run)"
        elif isinstance(v, (list, tuple)):
            text = ", ".join(quantity(x, unit) for x in v)
        elif v is None or (isinstance(v, float) and not math.isfinite(v)):
            text = "n/a"
        else:
            text = quantity(v, unit)
        trs.append(html.Tr([html.Td(LABELS.get(key, key.replace("_", " ")),
                                    style={"paddingRight": "10px", "verticalAlign": "top"}),
                            html.Td(text, id=f"sum-{key}", **{"data-value": json.dumps(v)},
                                    style={"whiteSpace": "nowrap" if len(text) < 24 else "normal"})]))
    return html.Table(html.Tbody(trs), style={"borderCollapse": "collapse"})


def redraw(pins, trace, cal, des, settings):
    """Callback: the figure again when pins, trace, calibration or design change."""
    return draw(settings, pins, trace, cal, des)


def page_hint(text: str) -> str:
    """A message worded for the page: it has a method field, not a max_step,
    and its t_end field is in ms."""
    text = text.replace("try method='bdf' or a max_step", "try the method bdf (beside t_end)")
    text = text.replace("method='bdf'", "the method bdf (beside t_end)")
    return re.sub(r"use t_end >= ([0-9.eE+-]+) s",
                  lambda m: f"set t_end to {float(m.group(1)) * 1e3:g} ms or more", text)


def stale_figure(text: str) -> dict:
    """An empty figure showing ``text`` (in red) where a curve cannot be drawn."""
    return {"data": [], "layout": {
        "height": 300, "xaxis": {"visible": False}, "yaxis": {"visible": False},
        "annotations": [{"text": text, "showarrow": False, "font": {"size": 14, "color": "#b00020"},
                         "xref": "paper", "yref": "paper", "x": 0.5, "y": 0.5}]}}


def run_args(settings) -> dict:
    """The run's t_end and method from the page's settings."""
    return {"t_end": settings.get("t_end"), "method": settings.get("method", "auto")}


def draw(settings, pins, trace, cal, des):
    """The run of the settings: its figure (with pins, trace and fits), its
    summary and a status line. A failed run clears the plot and the summary
    (they would show the last good run as if it were this one) and says why."""
    wb = workbench(settings["rig"])
    try:
        out = wb.outcome(settings["values"], **run_args(settings))
    except PdbfsError as err:
        msg = page_hint(str(err))
        summary = html.Div([html.H4("Summary", style={"margin": "4px 0"}),
                            html.Div("no result for these settings: the run failed",
                                     id="run-failed", style={"color": "#b00020"})])
        return (stale_figure("no result: the run failed (see the message above)"), summary,
                html.Span(msg, style={"color": "#b00020"}, id="status-error"))
    pinned = []
    for pin in pins or []:
        try:
            pinned.append((pin["label"], wb.outcome(pin["values"], **run_args(pin))["curves"]))
        except PdbfsError:
            continue
    overlays = []
    pressure_unit = "Pa"
    if trace:
        try:
            t, y = traces.load(trace)
            overlays.append((f"trace {trace['name']}", *traces.decimate(t, y), pressure_unit))
        except PdbfsError:
            pass
    for label, r in (("calibrated fit", cal), ("designed pulse", des)):
        if r and r.get("t") and r.get("fit"):
            overlays.append((label, r["t"], r["fit"], r.get("unit", pressure_unit)))
    fig = pulse_figure(out["curves"], pinned, overlays, title=f"rig {wb.name}",
                       labels={n: wb.curve_label(n) for n in out["curves"] if n != "t"})
    summary = html.Div([html.H4("Summary", style={"margin": "4px 0"}), _summary_table(out["rows"])])
    status = [f"backend {wb.backend}, method {settings.get('method', 'auto')}: {out['n']} points "
              f"to {quantity(out['t_last'], 's')}"]
    status += [html.Div(page_hint(note.split(": ", 1)[-1]), className="note",
                        style={"color": "#8a5a00"})
               for note in out["notes"]]
    return fig, summary, status


def edit_run(t_end, method, settings, pins, trace, cal, des):
    """The run length (ms) or the method changed: the run again, or the
    field's one-line message."""
    wb = workbench(settings["rig"])
    try:
        t, m = wb.check_run(t_end, method)
    except PdbfsError as err:
        return no_update, str(err), no_update, no_update, no_update
    old = settings.get("t_end") or t
    if abs(t - old) <= 1e-9 * old:        # the field's text of the same length
        t = old
    if t == settings.get("t_end") and m == settings.get("method"):
        return no_update, None, no_update, no_update, no_update
    settings = {**settings, "t_end": t, "method": m}
    return (settings, None) + draw(settings, pins, trace, cal, des)


def pin(_pin, _unpin, settings, pins):
    """Callback: keep the current curve (labelled by what changed) or clear the kept ones."""
    if ctx.triggered_id == "unpin":
        return []
    wb = workbench(settings["rig"])
    changed = [f"{k}={fmt(v)}" for k, v in settings["values"].items()
               if v != wb.defaults().get(k) and not (wb.height and k == wb.height.derived)]
    # numbered past every pin still shown: labels never repeat
    number = 1 + max([int(p["label"].split()[1]) for p in pins or []] + [0])
    label = f"pin {number}" + (f" ({', '.join(changed[:2])})" if changed else " (defaults)")
    new = {"label": label, "values": settings["values"], **run_args(settings)}
    return ((pins or []) + [new])[-MAX_PINS:]


def upload(data, settings):
    """Callback: read an uploaded trace (CSV) for calibration, or say why it cannot be read."""
    if not data:
        raise PreventUpdate
    wb = workbench(settings["rig"])
    filename, contents = data.get("name"), data.get("contents")
    try:
        tr = wb.read_upload(filename, contents)
        kept = traces.store(filename, tr.t, tr.y)
    except PdbfsError as err:
        return no_update, str(err), None, None
    info = (f"{kept['name']}: {kept['n']} samples, t = {quantity(kept['t0'], 's')} .. "
            f"{quantity(kept['t1'], 's')}")
    return kept, None, info, None


def change_rig(rig, settings):
    """Callback: another rig chosen: its controls, settings and figure."""
    if rig == settings["rig"]:
        raise PreventUpdate
    try:
        wb = workbench(rig)
    except PdbfsError as err:
        return (no_update,) * 18 + (str(err), str(err)) + (no_update,) * 3
    opts = free_options(wb)
    s = initial_settings(wb)
    p = study_defaults(wb)
    toggle = parts_toggle(wb)
    return (controls(wb, s["values"]), s, [], None, opts, opts, opts, opts,
            p["cal-free"], p["des-free"], p["map-x"], p["map-y"],
            fmt(p["map-x-lo"]), fmt(p["map-x-hi"]), fmt(p["map-y-lo"]), fmt(p["map-y-hi"]),
            fmt(s["t_end"] * 1e3), s["method"], f"backend: {wb.backend_note}", "",
            toggle["options"], toggle["value"], toggle["style"])


def show_parts(value, settings):
    """The parameters of repeated parts drawn too, or not."""
    parts = "parts" in (value or [])
    if parts == settings.get("parts", False):
        raise PreventUpdate
    wb = workbench(settings["rig"])
    return controls(wb, settings["values"], parts), {**settings, "parts": parts}


def download(_csv, _png, _json, settings):
    """Callback: the results as CSV, the plot as PNG or the settings as JSON, for download."""
    wb = workbench(settings["rig"])
    try:
        if ctx.triggered_id == "dl-csv":
            return dcc.send_bytes(wb.results_csv(settings["values"], **run_args(settings)),
                                  "results.csv"), None
        if ctx.triggered_id == "dl-png":
            return dcc.send_bytes(wb.results_png(settings["values"], **run_args(settings)),
                                  "results.png"), None
        if ctx.triggered_id == "dl-json":
            text = json.dumps(wb.settings_json(settings["values"], **run_args(settings)), indent=2)
            return dcc.send_string(text, "settings.json"), None
    except PdbfsError as err:
        return no_update, page_hint(str(err))
    raise PreventUpdate


def register(app):
    """Add the page's interactive callbacks (sliders, fields, pins, uploads, downloads) to ``app``."""
    app.callback(
        Output({"type": "slider", "name": ALL}, "value"),
        Output({"type": "slider", "name": ALL}, "min"),
        Output({"type": "slider", "name": ALL}, "max"),
        Output({"type": "slider", "name": ALL}, "marks"),
        Output({"type": "field", "name": ALL}, "value"),
        Output({"type": "msg", "name": ALL}, "children"),
        Output("settings", "data"),
        Output("pulse", "figure", allow_duplicate=True), Output("summary", "children", allow_duplicate=True),
        Output("status", "children", allow_duplicate=True),
        Input({"type": "slider", "name": ALL}, "value"),
        Input({"type": "field", "name": ALL}, "value"),
        Input("reset", "n_clicks"), Input("cal-apply", "n_clicks"), Input("des-apply", "n_clicks"),
        State("settings", "data"), State("cal", "data"), State("des", "data"),
        State({"type": "msg", "name": ALL}, "children"), State("pins", "data"), State("trace", "data"),
        prevent_initial_call=True)(edit_settings)
    app.callback(Output("pulse", "figure"), Output("summary", "children"), Output("status", "children"),
                 Input("pins", "data"), Input("trace", "data"), Input("cal", "data"),
                 Input("des", "data"), State("settings", "data"))(redraw)
    app.callback(Output("pins", "data"), Input("pin", "n_clicks"), Input("unpin", "n_clicks"),
                 State("settings", "data"), State("pins", "data"),
                 prevent_initial_call=True)(pin)
    app.callback(Output("trace", "data"), Output("upload-msg", "children"),
                 Output("trace-info", "children"), Output("upload-data", "data", allow_duplicate=True),
                 Input("upload-data", "data"), State("settings", "data"),
                 prevent_initial_call=True)(upload)
    app.callback(Output("settings", "data", allow_duplicate=True), Output("run-msg", "children"),
                 Output("pulse", "figure", allow_duplicate=True),
                 Output("summary", "children", allow_duplicate=True),
                 Output("status", "children", allow_duplicate=True),
                 Input("t-end", "value"), Input("method", "value"), State("settings", "data"),
                 State("pins", "data"), State("trace", "data"), State("cal", "data"),
                 State("des", "data"), prevent_initial_call=True)(edit_run)
    app.callback(Output("controls", "children"), Output("settings", "data", allow_duplicate=True),
                 Output("pins", "data", allow_duplicate=True), Output("cal", "data", allow_duplicate=True),
                 Output("cal-free", "options"), Output("des-free", "options"),
                 Output("map-x", "options"), Output("map-y", "options"),
                 Output("cal-free", "value"), Output("des-free", "value"),
                 Output("map-x", "value"), Output("map-y", "value"),
                 Output("map-x-lo", "value"), Output("map-x-hi", "value"),
                 Output("map-y-lo", "value"), Output("map-y-hi", "value"),
                 Output("t-end", "value"), Output("method", "value"),
                 Output("backend", "children"), Output("rig-note", "children", allow_duplicate=True),
                 Output("parts", "options"), Output("parts", "value"), Output("parts", "style"),
                 Input("rig", "value"), State("settings", "data"),
                 prevent_initial_call=True)(change_rig)
    app.callback(Output("controls", "children", allow_duplicate=True),
                 Output("settings", "data", allow_duplicate=True),
                 Input("parts", "value"), State("settings", "data"),
                 prevent_initial_call=True)(show_parts)
    app.callback(Output("download", "data"), Output("dl-msg", "children"),
                 Input("dl-csv", "n_clicks"), Input("dl-png", "n_clicks"), Input("dl-json", "n_clicks"),
                 State("settings", "data"), prevent_initial_call=True)(download)
