"""The page's long actions: calibration, design, the design map and the FMU.
Each runs as a Dash background callback, in a process of its own (the page
stays responsive, Cancel ends it, and a crash cannot take the server down),
reporting its progress (simulations run, points mapped) while it works."""
from __future__ import annotations

import tempfile
import threading
import time
from pathlib import Path

from dash import Input, Output, State, dcc, html, no_update

from pdbfs.errors import ParameterError, PdbfsError

from pdbfs.simulation import SUMMARY_UNITS

from . import traces
from .figures import map_figure
from .numbers import RESULT_DIGITS, quantity, short_description, with_std
from .workbench import parse_number, workbench

POLL = 400    # ms between the page's looks at a job's progress


def with_progress(set_progress, label, fn, unit="simulations"):
    """``fn(report)`` in a thread while its progress is shown: the count the
    API reports through ``report`` (simulations run, or points done of all)
    and the time spent; its result, or the PdbfsError it raised."""
    box, count = {}, {}

    def report(done, total=None):
        count["done"], count["total"] = done, total

    def work():
        try:
            box["value"] = fn(report)
        except PdbfsError as err:
            box["error"] = err
        except Exception as err:   # noqa: BLE001 - shown on the page, never a dead server
            box["error"] = RuntimeError(f"{type(err).__name__}: {err}")

    def line(state):
        done = count.get("done")
        what = "" if done is None else (f"{done} of {count['total']} {unit}, "
                                        if count.get("total") else f"{done} {unit}, ")
        return f"{label}: {what}{state} {time.perf_counter() - t0:.1f} s"

    t0 = time.perf_counter()
    th = threading.Thread(target=work, daemon=True)
    th.start()
    while th.is_alive():
        set_progress(line(""))
        th.join(0.25)
    set_progress(line("done in"))
    if "error" in box:
        raise box["error"]
    return box["value"]


def _error(err):
    return html.Div(str(err), style={"color": "#b00020"}, className="msg")


def shown(v, unit) -> str:
    """A value with its unit, in the unit the page shows (MPa, ms, kN, mm)."""
    return quantity(v, unit)


def _values_table(wb, values, std=None, units=None, note=None):
    """Fitted or designed values: each parameter by name and description,
    its value to the digits its deviation allows (5 without one) and unit."""
    rows = []
    cell = {"padding": "1px 10px 1px 0"}
    for name, v in values.items():
        s = (std or {}).get(name)
        unit = (units or {}).get(name, "")
        text = "undetermined" if v is None else with_std(v, s, RESULT_DIGITS)
        try:
            what = short_description(wb.control(name).description)
        except ValueError:                 # a value the study implies, not a control
            what = ""
        rows.append(html.Tr([html.Td(name, style=cell, title=what),
                             html.Td(what, style={**cell, "color": "#555", "fontSize": "12px"}),
                             html.Td(text, id=f"val-{name}", style={**cell, "textAlign": "right"}),
                             html.Td("" if unit == "1" else unit, style=cell)]))
    return html.Div([html.Table(html.Tbody(rows), style={"borderCollapse": "collapse"}),
                     html.Div(note or "", style={"fontSize": "12px"})])


def calibrate(set_progress, _n, settings, trace, free):
    """Background job: calibrate the free parameters to the uploaded trace."""
    wb = workbench(settings["rig"])
    if not trace:
        return None, _error("upload a trace first"), True
    if not free:
        return None, _error("choose the free parameters"), True
    try:
        ty = traces.load(trace)
        out = with_progress(set_progress, "calibrating",
                            lambda report: wb.calibrate(settings["values"], ty, free, report))
    except (PdbfsError, RuntimeError) as err:
        return None, _error(err), True
    note = f"RMS residual {quantity(out['rms_residual'], out['unit'])}"
    if out["undetermined"]:
        note += "; not determined by the trace: " + "; ".join(f"{k} ({v})" for k, v in
                                                              out["undetermined"].items())
    return out, _values_table(wb, out["params"], out["std"], out["units"], note), False


def design(set_progress, _n, settings, trace, mode, peak, duration, tpeak, free):
    """Background job: design for target features or the uploaded curve."""
    wb = workbench(settings["rig"])
    if not free:
        return None, _error("choose the free parameters"), True
    try:
        if mode == "curve":
            if not trace:
                return None, _error("upload a target curve first"), True
            target = traces.load(trace)
        else:
            target = {}
            for key, text, f in (("peak_pressure", peak, 1e6), ("pulse_duration", duration, 1e-3),
                                 ("time_of_peak", tpeak, 1e-3)):
                if text not in (None, ""):
                    target[key] = parse_number(key, text) * f
            if not target:
                raise ParameterError("give at least one target: peak, duration or time of peak")
        out = with_progress(set_progress, "designing",
                            lambda report: wb.design(settings["values"], target, free, report))
    except (PdbfsError, RuntimeError) as err:
        return None, _error(err), True
    feats = ", ".join(f"{k.replace('_', ' ')} {shown(v, SUMMARY_UNITS.get(k, ''))}"
                      for k, v in out["features"].items())
    note = ("reached" if out["reachable"] else f"not reachable: {out['limit']}") + \
        (f"; features: {feats}" if feats else "") + \
        (f"; RMS error {shown(out['rms_error'], out['unit'])}" if out["rms_error"] is not None else "")
    return out, _values_table(wb, out["params"], None, {**wb.units, **out["units"]}, note), False


def design_map(set_progress, _n, settings, x, xlo, xhi, y, ylo, yhi, n):
    """Background job: the design map over two parameters' ranges."""
    wb = workbench(settings["rig"])
    try:
        ax = (x, parse_number(f"{x} from", xlo), parse_number(f"{x} to", xhi))
        ay = (y, parse_number(f"{y} from", ylo), parse_number(f"{y} to", yhi))
        npts = parse_number("points per axis", n)
        if npts != int(npts) or not 3 <= npts <= 60:
            raise ParameterError(f"points per axis: {n} must be a whole number from 3 to 60")
        m = with_progress(set_progress, "mapping",
                          lambda report: wb.design_map(settings["values"], ax, ay, int(npts), report),
                          unit="points")
    except (PdbfsError, RuntimeError) as err:
        return no_update, {"display": "none"}, str(err)
    note = f"{m['failed']} points failed" if m["failed"] else None
    m.update(x_label=wb.label(x), y_label=wb.label(y))
    return map_figure(m), {"display": "block"}, note


def fmu(set_progress, _n, settings):
    """Background job: the rig's FMU at the page's settings, for download."""
    wb = workbench(settings["rig"])
    try:
        with tempfile.TemporaryDirectory(prefix="pdbfs-app-") as tmp:
            path = Path(tmp) / f"{wb.file_name}.fmu"
            with_progress(set_progress, "building the FMU", lambda report: wb.fmu(settings["values"], path))
            return dcc.send_bytes(path.read_bytes(), path.name), None
    except (PdbfsError, RuntimeError) as err:
        return no_update, str(err)


def register(app):
    """Add the background jobs' callbacks to ``app``."""
    common = {"background": True, "prevent_initial_call": True, "interval": POLL}
    app.callback(Output("cal", "data", allow_duplicate=True), Output("cal-out", "children"),
                 Output("cal-apply", "disabled"),
                 Input("cal-run", "n_clicks"), State("settings", "data"), State("trace", "data"),
                 State("cal-free", "value"), progress=Output("cal-progress", "children"),
                 running=[(Output("cal-run", "disabled"), True, False)],
                 cancel=[Input("cal-cancel", "n_clicks")], **common)(calibrate)
    app.callback(Output("des", "data"), Output("des-out", "children"), Output("des-apply", "disabled"),
                 Input("des-run", "n_clicks"), State("settings", "data"), State("trace", "data"),
                 State("des-mode", "value"), State("des-peak", "value"),
                 State("des-duration", "value"), State("des-tpeak", "value"),
                 State("des-free", "value"), progress=Output("des-progress", "children"),
                 running=[(Output("des-run", "disabled"), True, False)],
                 cancel=[Input("des-cancel", "n_clicks")], **common)(design)
    app.callback(Output("map", "figure"), Output("map", "style"), Output("map-msg", "children"),
                 Input("map-run", "n_clicks"), State("settings", "data"),
                 State("map-x", "value"), State("map-x-lo", "value"), State("map-x-hi", "value"),
                 State("map-y", "value"), State("map-y-lo", "value"), State("map-y-hi", "value"),
                 State("map-n", "value"), progress=Output("map-progress", "children"),
                 running=[(Output("map-run", "disabled"), True, False)],
                 cancel=[Input("map-cancel", "n_clicks")], **common)(design_map)
    app.callback(Output("download-fmu", "data"), Output("dl-msg", "children", allow_duplicate=True),
                 Input("dl-fmu", "n_clicks"), State("settings", "data"),
                 progress=Output("dl-progress", "children"),
                 running=[(Output("dl-fmu", "disabled"), True, False)], **common)(fmu)
