"""The rig workbench in the browser (``pdbfs app``): a Dash page over the
Python API, as the command line is a layer over it; no model logic here.

    workbench.py   a rig as the page sees it: controls, runs, uploads,
                   downloads, calibration, design, design map (no Dash)
    controls.py    a parameter as a field and a slider; the order the page lists
                   them in (the rig's key parameters first); a field's text read
    numbers.py     numbers as the page writes them: to their digits, in MPa, kN,
                   mm and ms, the unit beside
    traces.py      uploaded traces kept on the server by key, capped, decimated
    page.py        the layout; the session's state is kept in the browser tab
    interact.py    quick callbacks: settings, the run and its summary, pins
    jobs.py        long actions as background callbacks with progress
    browser.py     clientside callbacks: the server's heartbeat, upload size,
                   study tabs, notes while a rig is built or a job cancelled
    figures.py     the Plotly figures
    server.py      create_app(), serve()

May import: pdbfs.errors, pdbfs.simulation, pdbfs.studies, pdbfs.models,
pdbfs.components (laws) and the public API (pdbfs); it sits beside pdbfs.cli
and nothing below imports from here.
"""
from pdbfs.errors import require_extra

require_extra("app", "pdbfs.app, the workbench,")
from .server import create_app, serve  # noqa: E402

__all__ = ["create_app", "serve"]
