"""The page's layout: the rig's parameters (field, slider, message), the
pulse and its summary, and the panels for traces, calibration, design, the
design map and downloads. The session's state lives in the browser tab
(``dcc.Store`` in memory): the server keeps none, so two tabs never mix."""
from __future__ import annotations

from dash import dcc, html

from pdbfs.models import RIGS

from .workbench import Control, Workbench

FIELD = {"width": "7.5em", "fontFamily": "monospace"}
MSG = {"color": "#b00020", "fontSize": "12px", "minHeight": "0"}
BOX = {"border": "1px solid #ddd", "borderRadius": "6px", "padding": "8px", "margin": "6px 0"}


def fmt(v) -> str:
    return f"{v:.6g}"


def marks(c: Control, lo: float, hi: float) -> dict:
    return {lo: fmt(c.from_slider(lo)), hi: fmt(c.from_slider(hi))}


def control_row(c: Control, value: float):
    lo, hi = c.slider_range(value)
    label = f"{c.name} [{c.unit}]" + (" (log)" if c.log else "")
    return html.Div([
        html.Div([html.B(label, title=c.description),
                  dcc.Input(id={"type": "field", "name": c.name}, type="text", value=fmt(value),
                            debounce=True, style=FIELD, className="field")],
                 style={"display": "flex", "justifyContent": "space-between", "gap": "6px"}),
        html.Div(c.description, style={"fontSize": "11px", "color": "#555"}),
        dcc.Slider(id={"type": "slider", "name": c.name}, min=lo, max=hi, step=c.step,
                   value=c.to_slider(value), marks=marks(c, lo, hi), updatemode="drag",
                   included=False, allow_direct_input=False),
        html.Div(id={"type": "msg", "name": c.name}, style=MSG, className="msg"),
    ], style={"padding": "4px 0", "borderBottom": "1px solid #eee"}, className="control")


def controls(wb: Workbench, values: dict):
    return [control_row(c, values[c.name]) for c in wb.controls]


def initial_settings(wb: Workbench) -> dict:
    return {"rig": wb.name, "values": wb.defaults()}


def free_options(wb: Workbench):
    return [{"label": c.name, "value": c.name} for c in wb.controls]


def study_defaults(wb: Workbench) -> dict:
    """What the study panels offer first: the oil stiffness to calibrate, the
    drop height to design, both for a design map."""
    names = [c.name for c in wb.controls]
    first = wb.height.name if wb.height else ("h" if "h" in names else names[0])
    second = "oil.k" if "oil.k" in names else names[-1]
    return {"cal-free": [second], "des-free": [first], "map-x": first, "map-y": second}


def _button(id_, text, **kw):
    return html.Button(text, id=id_, n_clicks=0, style={"margin": "2px"}, **kw)


def _labelled(text, comp):
    return html.Label([html.Span(text, style={"marginRight": "4px"}), comp],
                      style={"marginRight": "10px", "display": "inline-block"})


def studies_panels(wb: Workbench):
    opts = free_options(wb)
    picks = study_defaults(wb)
    first, second = picks["map-x"], picks["map-y"]
    trace = html.Div([
        html.H4("Measured trace and calibration", style={"margin": "2px"}),
        dcc.Upload(id="upload", children=html.Div(["Drop a trace CSV here or ", html.A("choose one")]),
                   style={**BOX, "borderStyle": "dashed", "textAlign": "center"}),
        html.Div(id="upload-msg", style=MSG, className="msg"),
        html.Div(id="trace-info", style={"fontSize": "12px"}),
        _labelled("free", dcc.Dropdown(id="cal-free", options=opts, multi=True,
                                       value=picks["cal-free"],
                                       style={"minWidth": "18em"})),
        _button("cal-run", "Calibrate"), _button("cal-cancel", "Cancel"),
        _button("cal-apply", "Apply fitted values", disabled=True),
        html.Div(id="cal-progress", style={"fontSize": "12px", "color": "#555"}),
        html.Div(id="cal-out", className="result"),
    ], style=BOX)
    design = html.Div([
        html.H4("Design", style={"margin": "2px"}),
        dcc.RadioItems(id="des-mode", value="features", inline=True,
                       options=[{"label": "target features", "value": "features"},
                                {"label": "the uploaded curve", "value": "curve"}]),
        _labelled("peak (MPa)", dcc.Input(id="des-peak", type="text", value="150", style=FIELD)),
        _labelled("duration (ms)", dcc.Input(id="des-duration", type="text", value="", style=FIELD)),
        _labelled("time of peak (ms)", dcc.Input(id="des-tpeak", type="text", value="", style=FIELD)),
        _labelled("free", dcc.Dropdown(id="des-free", options=opts, multi=True, value=[first],
                                       style={"minWidth": "18em"})),
        _button("des-run", "Design"), _button("des-cancel", "Cancel"),
        _button("des-apply", "Apply designed values", disabled=True),
        html.Div(id="des-progress", style={"fontSize": "12px", "color": "#555"}),
        html.Div(id="des-out", className="result"),
    ], style=BOX)
    dmap = html.Div([
        html.H4("Design map", style={"margin": "2px"}),
        _labelled("x", dcc.Dropdown(id="map-x", options=opts, value=first, style={"minWidth": "12em"})),
        _labelled("from", dcc.Input(id="map-x-lo", type="text", value="0.1", style=FIELD)),
        _labelled("to", dcc.Input(id="map-x-hi", type="text", value="1.5", style=FIELD)),
        html.Br(),
        _labelled("y", dcc.Dropdown(id="map-y", options=opts, value=second, style={"minWidth": "12em"})),
        _labelled("from", dcc.Input(id="map-y-lo", type="text", value="1e8", style=FIELD)),
        _labelled("to", dcc.Input(id="map-y-hi", type="text", value="1e9", style=FIELD)),
        _labelled("points per axis", dcc.Input(id="map-n", type="text", value="15", style=FIELD)),
        _button("map-run", "Map"), _button("map-cancel", "Cancel"),
        html.Div(id="map-progress", style={"fontSize": "12px", "color": "#555"}),
        html.Div(id="map-msg", style=MSG, className="msg"),
        dcc.Graph(id="map", style={"display": "none"}, config={"displaylogo": False}),
    ], style=BOX)
    downloads = html.Div([
        html.H4("Downloads", style={"margin": "2px"}),
        _button("dl-csv", "results.csv"), _button("dl-png", "results.png"),
        _button("dl-json", "settings.json"), _button("dl-fmu", "FMU (current settings)"),
        html.Div(id="dl-progress", style={"fontSize": "12px", "color": "#555"}),
        html.Div(id="dl-msg", style=MSG, className="msg"),
        dcc.Download(id="download"), dcc.Download(id="download-fmu"),
    ], style=BOX)
    return [trace, design, dmap, downloads]


def layout(wb: Workbench):
    settings = initial_settings(wb)
    head = html.Div([
        html.H2("pdbfs workbench", style={"margin": "0 12px 0 0"}),
        _labelled("rig", dcc.Dropdown(id="rig", options=list(RIGS), value=wb.name, clearable=False,
                                      style={"minWidth": "12em"})),
        html.Span(id="backend", children=f"backend: {wb.backend_note}",
                  style={"fontSize": "12px", "color": "#555"}),
    ], style={"display": "flex", "alignItems": "center", "gap": "8px"})
    left = html.Div(id="controls", children=controls(wb, settings["values"]),
                    style={"width": "360px", "flex": "0 0 360px", "overflowY": "auto",
                           "maxHeight": "calc(100vh - 80px)", "paddingRight": "8px",
                           "overflowX": "hidden"})
    plot = html.Div([
        html.Div([_button("pin", "Pin this curve"), _button("unpin", "Clear pins"),
                  _button("reset", "Reset to defaults"),
                  html.Span(id="status", style={"marginLeft": "10px", "fontSize": "12px"})]),
        html.Div([
            dcc.Graph(id="pulse", style={"flex": "1 1 auto"},
                      config={"displaylogo": False,
                              "toImageButtonOptions": {"format": "png", "filename": "pulse"}}),
            html.Div(id="summary", style={"flex": "0 0 260px", "fontSize": "13px"}),
        ], style={"display": "flex", "gap": "8px"}),
        html.Div(studies_panels(wb), id="studies"),
    ], style={"flex": "1 1 auto", "minWidth": "0"})
    stores = [dcc.Store(id="settings", data=settings, storage_type="memory"),
              dcc.Store(id="pins", data=[], storage_type="memory"),
              dcc.Store(id="trace", data=None, storage_type="memory"),
              dcc.Store(id="cal", data=None, storage_type="memory"),
              dcc.Store(id="des", data=None, storage_type="memory")]
    return html.Div([head, html.Div([left, plot], style={"display": "flex", "gap": "12px"}),
                     *stores], style={"fontFamily": "sans-serif", "margin": "8px"})
