"""The Dash app of a rig and the local server that runs it. Every asset
(Dash's and Plotly's JavaScript) is served from the installed packages:
the page works with no internet."""
from __future__ import annotations

import atexit
import shutil
import tempfile
import threading
import webbrowser

from . import interact, jobs
from .page import layout
from .workbench import workbench


def create_app(rig: str = "paper", cache_dir=None):
    """The page of ``rig`` as a Dash app (``app.run(...)`` serves it). Long
    actions run through a disk cache in ``cache_dir`` (default: a new
    temporary folder)."""
    import diskcache
    from dash import Dash, DiskcacheManager

    wb = workbench(rig)                      # bad rig names fail here, before serving
    if cache_dir is None:
        cache_dir = tempfile.mkdtemp(prefix="pdbfs-app-cache-")
        atexit.register(shutil.rmtree, cache_dir, True)
    cache = diskcache.Cache(cache_dir)
    app = Dash(__name__, title=f"pdbfs workbench: {rig}", serve_locally=True,
               background_callback_manager=DiskcacheManager(cache),
               suppress_callback_exceptions=True, update_title=None)
    app.layout = lambda: layout(workbench(wb.name))   # a fresh page (and state) per load
    interact.register(app)
    jobs.register(app)
    return app


def serve(rig: str = "paper", host: str = "127.0.0.1", port: int = 8050, open_browser=False,
          ready=None):
    """Serve the page until interrupted; ``ready(url)`` is called once it is built."""
    app = create_app(rig)
    url = f"http://{host}:{port}/"
    if ready:
        ready(url)
    if open_browser:
        threading.Timer(1.0, webbrowser.open, args=(url,)).start()
    app.run(host=host, port=port, debug=False, threaded=True)
