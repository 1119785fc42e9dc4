"""What the page does in the browser alone (clientside callbacks, no round
trip): whether the server is still there, the size of an upload before it
is sent, the study tab shown, and notes while a rig is built or after a
job was cancelled."""
from __future__ import annotations

from dash import Input, Output, State

from .page import TABS
from .traces import MAX_UPLOAD

ALIVE = "/_pdbfs/alive"

# The heartbeat asks the server; a failed or refused request shows the banner.
HEARTBEAT = """
async function(n) {
    try {
        const r = await fetch('%s', {cache: 'no-store'});
        if (r.ok) { return {display: 'none'}; }
    } catch (e) {}
    return {display: 'block', position: 'fixed', top: 0, left: 0, right: 0, zIndex: 1000,
            padding: '8px', background: '#b00020', color: 'white', fontWeight: 'bold'};
}
""" % ALIVE.lstrip("/")

# A file over the limit is refused here, before its contents travel.
UPLOAD = """
function(contents, name) {
    const keep = window.dash_clientside.no_update;
    if (!contents) { return [keep, keep, keep]; }
    const bytes = Math.floor((contents.length - contents.indexOf(',') - 1) * 3 / 4);
    if (bytes > %d) {
        const shown = JSON.stringify(String(name)).slice(1, -1);
        return [null, "trace file '" + shown + "': " + (bytes / 1e6).toFixed(1) +
                " MB, more than the page takes (%d MB); thin it out, or use pdbfs calibrate " +
                "--trace on the command line", null];
    }
    return [{name: name, contents: contents}, null, "reading " + String(name) + " ..."];
}
""" % (MAX_UPLOAD, MAX_UPLOAD // 1_000_000)

TAB = """
function(tab) {
    return %s.map(k => Object.assign({}, {border: '1px solid #ddd', borderRadius: '6px',
                                           padding: '8px', margin: '6px 0'},
                                      {display: k === tab ? 'block' : 'none'}));
}
""" % str([k for k, _ in TABS])

RIG_NOTE = """
function(rig) {
    return "building rig " + rig + " (the first time it is compiled: up to half a minute) ...";
}
"""

# said only of a job that was running (its button is disabled while it runs)
CANCELLED = """
function(n, running) {
    return n && running ? "cancelled at " + new Date().toLocaleTimeString() +
                          ": nothing was changed" : window.dash_clientside.no_update;
}
"""


def register(app):
    """Add the liveness route and the page's heartbeat (a lost server is said on the page) to ``app``."""
    @app.server.route(ALIVE)
    def alive():
        return "ok"

    app.clientside_callback(HEARTBEAT, Output("conn-lost", "style"),
                            Input("heartbeat", "n_intervals"))
    app.clientside_callback(UPLOAD, Output("upload-data", "data", allow_duplicate=True),
                            Output("upload-msg", "children", allow_duplicate=True),
                            Output("trace-info", "children", allow_duplicate=True),
                            Input("upload", "contents"), State("upload", "filename"),
                            prevent_initial_call=True)
    app.clientside_callback(TAB, [Output(f"panel-{k}", "style") for k, _ in TABS],
                            Input("study-tab", "value"))
    app.clientside_callback(RIG_NOTE, Output("rig-note", "children"), Input("rig", "value"),
                            prevent_initial_call=True)
    for job in ("cal", "des", "map"):
        app.clientside_callback(CANCELLED, Output(f"{job}-progress", "children",
                                                  allow_duplicate=True),
                                Input(f"{job}-cancel", "n_clicks"), State(f"{job}-run", "disabled"),
                                prevent_initial_call=True)
