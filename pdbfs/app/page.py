"""The page's layout: the rig's parameters (field, slider, message), the
pulse and its summary, and the panels for traces, calibration, design, the
design map and downloads. The session's state lives in the browser tab
(``dcc.Store`` in memory): the server keeps none, so two tabs never mix."""
from __future__ import annotations

from dash import dcc, html


from .controls import KEY, START_GROUP
from .numbers import DERIVED_DIGITS, GIVEN_DIGITS, MARK_DIGITS, number
from .traces import MAX_UPLOAD
from .workbench import METHODS, Control, Workbench, rig_names

FIELD = {"width": "7.5em", "fontFamily": "monospace"}
MSG = {"color": "#b00020", "fontSize": "12px", "minHeight": "0"}
#: the study panels, one shown at a time (key, tab label)
TABS = (("trace", "Trace and calibration"), ("design", "Design"), ("map", "Design map"),
        ("downloads", "Downloads"))
HEARTBEAT = 2000     # ms between the page's looks at whether the server is there
BOX = {"border": "1px solid #ddd", "borderRadius": "6px", "padding": "8px", "margin": "6px 0"}


#: the titles of the sidebar's groups that are no component's
GROUPS = {KEY: "Main settings", "": "Rig", START_GROUP: "Start positions, velocities, pressures"}
GROUP_STYLE = {"fontSize": "12px", "fontWeight": "bold", "color": "#444", "textTransform": "uppercase",
               "letterSpacing": "0.04em", "margin": "10px 0 0", "padding": "2px 0",
               "borderBottom": "2px solid #ccc"}


def fmt(v) -> str:
    """A setting as given (a default, a range's end): up to 6 digits."""
    return number(v, GIVEN_DIGITS)


def field_text(c: Control, value: float, derived: bool = False) -> str:
    """A field's text: a setting as given to 6 digits; one derived from
    another (a drop height and its impact speed) to 4."""
    return number(value, DERIVED_DIGITS if derived or c.derived else GIVEN_DIGITS)


def marks(c: Control, lo: float, hi: float) -> dict:
    """A slider's end marks, as values."""
    return {lo: number(c.from_slider(lo), MARK_DIGITS), hi: number(c.from_slider(hi), MARK_DIGITS)}


def group_title(group: str) -> str:
    """A sidebar group's title: a component's name, or what the group holds."""
    return GROUPS.get(group, group)


def control_row(c: Control, value: float):
    """One parameter's row: label with unit, slider and field."""
    lo, hi = c.slider_range(value)
    label = f"{c.name} [{c.unit}]" + (" (log)" if c.log else "")
    return html.Div([
        html.Div([html.B(label, title=c.description),
                  dcc.Input(id={"type": "field", "name": c.name}, type="text",
                            value=field_text(c, value), debounce=True, style=FIELD,
                            className="field")],
                 style={"display": "flex", "justifyContent": "space-between", "gap": "6px"}),
        html.Div(c.description, style={"fontSize": "11px", "color": "#555", "marginBottom": "4px"},
                 className="description"),
        # side padding: the end marks are centred on the ends and would be clipped
        html.Div(dcc.Slider(id={"type": "slider", "name": c.name}, min=lo, max=hi, step=c.step,
                            value=c.to_slider(value), marks=marks(c, lo, hi), updatemode="drag",
                            included=False, allow_direct_input=False),
                 style={"padding": "0 34px"}, className="slider-box"),
        html.Div(id={"type": "msg", "name": c.name}, style=MSG, className="msg"),
    ], style={"padding": "4px 0", "borderBottom": "1px solid #eee"}, className="control")


def controls(wb: Workbench, values: dict, parts: bool = False):
    """The sidebar's controls in the rig's groups, each under its title."""
    out = []
    for group, cs in wb.shown_groups(parts):
        out.append(html.Div(group_title(group), className="group", style=GROUP_STYLE))
        out += [control_row(c, values[c.name]) for c in cs]
    return out


def parts_toggle(wb: Workbench):
    """The checkbox that draws the parameters of repeated parts too (hidden
    for a rig without them)."""
    note = wb.parts_note()
    return {"options": [{"label": " " + note, "value": "parts"}] if note else [], "value": [],
            "style": {"fontSize": "12px", "display": "block" if note else "none"}}


def initial_settings(wb: Workbench) -> dict:
    """The page's settings on opening: the rig's defaults."""
    return {"rig": wb.name, "values": wb.defaults(), "t_end": wb.t_end, "method": "auto",
            "parts": False}


def free_options(wb: Workbench):
    """The parameters a study may free, named and described, with the unit."""
    return [{"label": wb.label(c.name) + (f" [{c.unit}]" if c.unit != "1" else ""),
             "value": c.name, "title": c.description} for c in wb.controls]


def study_defaults(wb: Workbench) -> dict:
    """What the study panels offer first: the rig's own declaration."""
    return wb.study_defaults()


def _button(id_, text, **kw):
    return html.Button(text, id=id_, n_clicks=0, style={"margin": "2px"}, **kw)


def _labelled(text, comp):
    return html.Label([html.Span(text, style={"marginRight": "4px"}), comp],
                      style={"marginRight": "10px", "display": "inline-flex", "alignItems": "center"})


def studies_panels(wb: Workbench):
    """The calibration, design, design map and FMU panels."""
    opts = free_options(wb)
    picks = study_defaults(wb)
    first, second = picks["map-x"], picks["map-y"]
    lim = f"at most {MAX_UPLOAD / 1e6:.0f} MB"
    trace = html.Div([
        html.H4("Measured trace and calibration", style={"margin": "2px"}),
        dcc.Upload(id="upload", children=html.Div(["Drop a trace CSV here or ", html.A("choose one"),
                                                      f" ({lim})"]),
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
        _labelled("peak pressure [MPa]", dcc.Input(id="des-peak", type="text", value="150", style=FIELD)),
        _labelled("pulse duration [ms]", dcc.Input(id="des-duration", type="text", value="", style=FIELD)),
        _labelled("time of peak [ms]", dcc.Input(id="des-tpeak", type="text", value="", style=FIELD)),
        _labelled("free", dcc.Dropdown(id="des-free", options=opts, multi=True,
                                       value=picks["des-free"],
                                       style={"minWidth": "18em"})),
        _button("des-run", "Design"), _button("des-cancel", "Cancel"),
        _button("des-apply", "Apply designed values", disabled=True),
        html.Div(id="des-progress", style={"fontSize": "12px", "color": "#555"}),
        html.Div(id="des-out", className="result"),
    ], style=BOX)
    dmap = html.Div([
        html.H4("Design map", style={"margin": "2px"}),
        _labelled("x", dcc.Dropdown(id="map-x", options=opts, value=first, style={"minWidth": "12em"})),
        _labelled("from", dcc.Input(id="map-x-lo", type="text", value=fmt(picks["map-x-lo"]),
                                         style=FIELD)),
        _labelled("to", dcc.Input(id="map-x-hi", type="text", value=fmt(picks["map-x-hi"]),
                                       style=FIELD)),
        html.Br(),
        _labelled("y", dcc.Dropdown(id="map-y", options=opts, value=second, style={"minWidth": "12em"})),
        _labelled("from", dcc.Input(id="map-y-lo", type="text", value=fmt(picks["map-y-lo"]),
                                         style=FIELD)),
        _labelled("to", dcc.Input(id="map-y-hi", type="text", value=fmt(picks["map-y-hi"]),
                                       style=FIELD)),
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
    panels = [trace, design, dmap, downloads]
    for k, panel in enumerate(panels):
        panel.id = f"panel-{TABS[k][0]}"
        panel.style = {**BOX, "display": "block" if k == 0 else "none"}
    return panels


def run_row(wb: Workbench, settings: dict):
    """The run's length and the integrator's method, and the status line."""
    return html.Div([
        _button("pin", "Pin this curve"), _button("unpin", "Clear pins"),
        _labelled("t_end [ms]", dcc.Input(id="t-end", type="text", value=fmt(settings["t_end"] * 1e3),
                                          debounce=True, style=FIELD)),
        _labelled("method", dcc.Dropdown(id="method", options=list(METHODS), value=settings["method"],
                                         clearable=False, style={"minWidth": "6em"})),
        html.Span(id="run-msg", style=MSG, className="msg"),
        html.Div(id="status", style={"fontSize": "12px", "minHeight": "1.2em"}),
    ], style={"display": "flex", "flexWrap": "wrap", "alignItems": "center", "columnGap": "10px"})


RESET = "Every parameter back to the rig's default; the run's t_end and method stay as they are"
INTRO = ("A drop-hammer test rig as a model: each parameter on the left has a field and a "
         "slider; any change runs the rig again and redraws the pressure pulse, the contact "
         "force and the displacements, with the summary beside them. Pin a curve to compare "
         "the next. Below the plot: lay a measured trace over the pulse and calibrate "
         "parameters to it, design for a peak or duration, map two settings, download results. "
         "The rig's main settings come first, its start positions last.")


def layout(wb: Workbench):
    """The whole page for the rig of ``wb``."""
    settings = initial_settings(wb)
    head = html.Div([
        html.H2("pdbfs workbench", style={"margin": "0 12px 0 0"}),
        _labelled("rig", dcc.Dropdown(id="rig", options=rig_names(), value=wb.name, clearable=False,
                                      style={"minWidth": "12em"})),
        html.Span(id="rig-note", style={"fontSize": "13px", "color": "#8a5a00"}),
        html.Span(id="backend", children=f"backend: {wb.backend_note}",
                  style={"fontSize": "12px", "color": "#555"}),
    ], style={"display": "flex", "alignItems": "center", "gap": "8px"})
    intro = html.Details([html.Summary("What is this page?"), html.P(INTRO, style={"margin": "4px"})],
                         id="intro", style={"fontSize": "13px", "margin": "4px 0"})
    lost = html.Div("The connection to the pdbfs server is lost: edits are not simulated. "
                    "Start `pdbfs app` again and reload the page.", id="conn-lost",
                    style={"display": "none", "position": "fixed", "top": "0", "left": "0",
                           "right": "0", "zIndex": "1000", "padding": "8px",
                           "background": "#b00020", "color": "white", "fontWeight": "bold"})
    top = html.Div([html.B("Parameters", style={"fontSize": "15px"}),
                    _button("reset", "Reset parameters", title=RESET)],
                   style={"display": "flex", "justifyContent": "space-between",
                          "alignItems": "center"})
    left = html.Div([top, dcc.Checklist(id="parts", **parts_toggle(wb)),
                     html.Div(id="controls", children=controls(wb, settings["values"]))],
                    style={"width": "360px", "flex": "0 0 360px", "overflowY": "auto",
                           "maxHeight": "calc(100vh - 80px)", "paddingRight": "8px",
                           "overflowX": "hidden"})
    tabs = dcc.RadioItems(id="study-tab", value=TABS[0][0], inline=True,
                          options=[{"label": text, "value": key} for key, text in TABS],
                          className="tabs", inputStyle={"marginRight": "4px"},
                          labelStyle={"marginRight": "14px", "padding": "4px 8px",
                                      "border": "1px solid #ccc", "borderRadius": "6px 6px 0 0"})
    plot = html.Div([
        run_row(wb, settings),
        dcc.Loading(html.Div([
            dcc.Graph(id="pulse", style={"flex": "1 1 auto"},
                      config={"displaylogo": False,
                              "toImageButtonOptions": {"format": "png", "filename": "pulse"}}),
            html.Div(id="summary", style={"flex": "0 0 260px", "fontSize": "13px"}),
        ], style={"display": "flex", "gap": "8px"}), delay_show=400, overlay_style={
            "visibility": "visible", "opacity": 0.45}, custom_spinner=html.B(
                "simulating ...", id="busy", style={"fontSize": "16px", "color": "#8a5a00"})),
        tabs,
        html.Div(studies_panels(wb), id="studies"),
    ], style={"flex": "1 1 auto", "minWidth": "0"})
    stores = [dcc.Store(id="settings", data=settings, storage_type="memory"),
              dcc.Store(id="pins", data=[], storage_type="memory"),
              dcc.Store(id="trace", data=None, storage_type="memory"),
              dcc.Store(id="upload-data", data=None, storage_type="memory"),
              dcc.Store(id="cal", data=None, storage_type="memory"),
              dcc.Store(id="des", data=None, storage_type="memory"),
              dcc.Interval(id="heartbeat", interval=HEARTBEAT)]
    return html.Div([lost, head, intro, html.Div([left, plot], style={"display": "flex", "gap": "12px"}),
                     *stores], style={"fontFamily": "sans-serif", "margin": "8px"})
