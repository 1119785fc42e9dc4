"""The page's quick callbacks (each a millisecond or so of work): settings
edited by a field, a slider, reset or apply; the run and its summary; pins;
the uploaded trace; the small downloads. A PdbfsError is shown next to what
caused it, never raised: the server does not die of bad input."""
from __future__ import annotations

import json
import math

from dash import ALL, Input, Output, State, ctx, dcc, html, no_update
from dash.exceptions import PreventUpdate

from pdbfs.errors import PdbfsError

from .figures import pulse_figure
from .page import controls, fmt, free_options, initial_settings, marks, study_defaults
from .workbench import workbench

MAX_PINS = 5
LABELS = {"peak_pressure": "peak pressure", "time_of_peak": "time of peak",
          "pulse_duration": "pulse duration", "complete": "complete",
          "peak_contact_force": "peak contact force",
          "max_piston_displacement": "max. piston displacement",
          "restitution_coefficient": "restitution"}
SHOWN = {"Pa": (1e-6, "MPa"), "s": (1e3, "ms"), "N": (1e-3, "kN"), "m": (1e3, "mm")}


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
    names = [c.name for c in wb.controls]
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
        c = wb.controls[k]
        if trig["type"] == "slider":
            s = slider_vals[k]
            if s is None or abs(s - c.to_slider(values[name])) < c.step / 2:
                raise PreventUpdate           # a slider settling on its step: not a change
            text = fmt(c.from_slider(s))
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
    for k, (c, name) in enumerate(zip(wb.controls, names)):
        v = values[name]
        lo, hi = c.slider_range(v)
        moved = name in changed
        slider_moved = isinstance(trig, dict) and trig["type"] == "slider" and trig["name"] == name
        out_s.append(c.to_slider(v) if moved and not slider_moved else no_update)
        out_lo.append(lo if moved else no_update)
        out_hi.append(hi if moved else no_update)
        out_m.append(marks(c, lo, hi) if moved else no_update)
        field_typed = isinstance(trig, dict) and trig["type"] == "field" and trig["name"] == name
        out_f.append(texts.get(name, fmt(v)) if moved and not field_typed else no_update)
        if moved and msgs[k] and not field_typed:
            msgs[k] = None
    settings = {**settings, "values": values}
    return (out_s, out_lo, out_hi, out_m, out_f, msgs, settings) + draw(settings, pins, trace, cal, des)


def _summary_table(rows):
    trs = []
    for key, v, unit in rows:
        f, shown = SHOWN.get(unit, (1.0, unit if unit != "1" else ""))
        if isinstance(v, bool):
            text = "yes" if v else "no (cut off at the end of the run)"
        elif isinstance(v, (list, tuple)):
            text = ", ".join(fmt(x * f) for x in v) + f" {shown}"
        elif v is None or (isinstance(v, float) and not math.isfinite(v)):
            text = "n/a"
        else:
            text = f"{fmt(v * f)} {shown}".strip()
        trs.append(html.Tr([html.Td(LABELS.get(key, key)),
                            html.Td(text, id=f"sum-{key}", **{"data-value": json.dumps(v)})]))
    return html.Table(html.Tbody(trs), style={"borderCollapse": "collapse"})


def redraw(pins, trace, cal, des, settings):
    return draw(settings, pins, trace, cal, des)


def draw(settings, pins, trace, cal, des):
    """The run of the settings: its figure (with pins, trace and fits), its
    summary and a status line; a PdbfsError goes to the status line."""
    wb = workbench(settings["rig"])
    try:
        res = wb.run(settings["values"])
        rows = wb.summary(res)
    except PdbfsError as err:
        return no_update, no_update, html.Span(str(err), style={"color": "#b00020"})
    pinned = []
    for pin in pins or []:
        try:
            pinned.append((pin["label"], wb.curves(wb.run(pin["values"]))))
        except PdbfsError:
            continue
    overlays = []
    pressure_unit = "Pa"
    if trace:
        overlays.append((f"trace {trace['name']}", trace["t"], trace["y"], pressure_unit))
    for label, r in (("calibrated fit", cal), ("designed pulse", des)):
        if r and r.get("t") and r.get("fit"):
            overlays.append((label, r["t"], r["fit"], r.get("unit", pressure_unit)))
    fig = pulse_figure(wb.curves(res), pinned, overlays, title=f"rig {wb.name}")
    summary = html.Div([html.H4("Summary", style={"margin": "4px 0"}), _summary_table(rows)])
    return fig, summary, f"backend {wb.backend}: {len(res.t)} points to {fmt(res.t[-1] * 1e3)} ms"


def pin(_pin, _unpin, settings, pins):
    if ctx.triggered_id == "unpin":
        return []
    wb = workbench(settings["rig"])
    changed = [f"{k}={fmt(v)}" for k, v in settings["values"].items()
               if v != wb.defaults().get(k) and not (wb.height and k == wb.height.derived)]
    label = f"pin {len(pins or []) + 1}" + (f" ({', '.join(changed[:2])})" if changed else " (defaults)")
    return ((pins or []) + [{"label": label, "values": settings["values"]}])[-MAX_PINS:]


def upload(contents, filename, settings):
    if contents is None:
        raise PreventUpdate
    wb = workbench(settings["rig"])
    try:
        tr = wb.read_upload(filename, contents)
    except PdbfsError as err:
        return no_update, str(err), no_update
    info = f"{filename}: {len(tr.t)} samples, t = {fmt(tr.t[0])} .. {fmt(tr.t[-1])} s"
    data = {"name": filename, "t": [float(x) for x in tr.t], "y": [float(x) for x in tr.y]}
    return data, None, info


def change_rig(rig, settings):
    if rig == settings["rig"]:
        raise PreventUpdate
    try:
        wb = workbench(rig)
    except PdbfsError as err:
        return (no_update,) * 12 + (str(err),)
    opts = free_options(wb)
    s = initial_settings(wb)
    picks = study_defaults(wb)
    return (controls(wb, s["values"]), s, [], None, opts, opts, opts, opts,
            picks["cal-free"], picks["des-free"], picks["map-x"], picks["map-y"],
            f"backend: {wb.backend_note}")


def download(_csv, _png, _json, settings):
    wb = workbench(settings["rig"])
    try:
        if ctx.triggered_id == "dl-csv":
            return dcc.send_bytes(wb.results_csv(settings["values"]), "results.csv"), None
        if ctx.triggered_id == "dl-png":
            return dcc.send_bytes(wb.results_png(settings["values"]), "results.png"), None
        if ctx.triggered_id == "dl-json":
            text = json.dumps(wb.settings_json(settings["values"]), indent=2)
            return dcc.send_string(text, "settings.json"), None
    except PdbfsError as err:
        return no_update, str(err)
    raise PreventUpdate


def register(app):
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
                 Output("trace-info", "children"),
                 Input("upload", "contents"), State("upload", "filename"), State("settings", "data"),
                 prevent_initial_call=True)(upload)
    app.callback(Output("controls", "children"), Output("settings", "data", allow_duplicate=True),
                 Output("pins", "data", allow_duplicate=True), Output("cal", "data", allow_duplicate=True),
                 Output("cal-free", "options"), Output("des-free", "options"),
                 Output("map-x", "options"), Output("map-y", "options"),
                 Output("cal-free", "value"), Output("des-free", "value"),
                 Output("map-x", "value"), Output("map-y", "value"), Output("backend", "children"),
                 Input("rig", "value"), State("settings", "data"),
                 prevent_initial_call=True)(change_rig)
    app.callback(Output("download", "data"), Output("dl-msg", "children"),
                 Input("dl-csv", "n_clicks"), Input("dl-png", "n_clicks"), Input("dl-json", "n_clicks"),
                 State("settings", "data"), prevent_initial_call=True)(download)
