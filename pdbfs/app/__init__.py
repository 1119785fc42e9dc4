"""The rig workbench in the browser (``pdbfs app``): a Dash page over the
Python API, as the command line is a layer over it; no model logic here.

    workbench.py   a rig as the page sees it: controls, runs, uploads,
                   downloads, calibration, design, design map (no Dash)
    page.py        the layout; the session's state is kept in the browser tab
    interact.py    quick callbacks: settings, the run and its summary, pins
    jobs.py        long actions as background callbacks with progress
    figures.py     the Plotly figures
    server.py      create_app(), serve()

May import: pdbfs.errors, pdbfs.simulation, pdbfs.studies, pdbfs.models,
pdbfs.components (laws) and the public API (pdbfs); it sits beside pdbfs.cli
and nothing below imports from here.
"""
from .server import create_app, serve

__all__ = ["create_app", "serve"]
