"""The Dash app of a rig and the local server that runs it. Every asset
(Dash's and Plotly's JavaScript) is served from the installed packages:
the page works with no internet."""
from __future__ import annotations

import atexit
import logging
import os
import shutil
import signal
import socket
import sys
import tempfile
import threading
import webbrowser

from pdbfs.errors import ParameterError

from . import browser, interact, jobs, traces
from .page import layout
from .workbench import offer, workbench

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def create_app(rig: str = "paper", cache_dir=None):
    """The page of ``rig`` as a Dash app (``app.run(...)`` serves it). Long
    actions run through a disk cache in ``cache_dir`` (default: a new
    temporary folder)."""
    import diskcache
    from dash import Dash, DiskcacheManager

    offer(rig)                               # a user's rig (FILE.py:NAME) on the page too
    wb = workbench(rig)                      # bad rig names fail here, before serving
    if cache_dir is None:
        cache_dir = tempfile.mkdtemp(prefix="pdbfs-app-cache-")
        atexit.register(shutil.rmtree, cache_dir, True)
    # uploaded traces beside the jobs' cache; the jobs' processes inherit the variable
    os.environ[traces.ENV] = os.path.join(cache_dir, "traces")
    cache = diskcache.Cache(cache_dir)
    app = Dash(__name__, title=f"pdbfs workbench: {rig}", serve_locally=True,
               background_callback_manager=DiskcacheManager(cache),
               suppress_callback_exceptions=True, update_title=None)
    app.layout = lambda: layout(workbench(wb.name))   # a fresh page (and state) per load
    # a request larger than an upload the page takes is refused by Flask
    app.server.config["MAX_CONTENT_LENGTH"] = int(traces.MAX_UPLOAD * 1.4) + 2_000_000
    interact.register(app)
    jobs.register(app)
    browser.register(app)
    return app


def serve(rig: str = "paper", host: str = "127.0.0.1", port: int = 8050, open_browser=False,
          ready=None):
    """Serve the page until interrupted; ``ready(url)`` is called once it is built."""
    if host.startswith("[") and host.endswith("]"):     # an IPv6 address as a URL writes it
        host = host[1:-1]
    check_address(host, port)
    if host not in LOOPBACK:
        print(f"pdbfs: warning: --host {host}: the page is open to every machine that can reach "
              "this one (no login; anyone may run simulations and upload files); use --host "
              "127.0.0.1 to keep it to this machine", file=sys.stderr, flush=True)
    # SIGTERM ends the server as Ctrl-C does, so the cache folder is removed (atexit)
    signal.signal(signal.SIGTERM, _terminate)
    app = create_app(rig)
    logging.getLogger("werkzeug").setLevel(logging.ERROR)   # no line per request
    url = page_url(host, port)
    if ready:
        ready(url)
    if open_browser:
        threading.Timer(1.0, webbrowser.open, args=(url,)).start()
    # the server returns quietly from a Ctrl-C (werkzeug catches it): noted here and
    # raised again, so that the command says so and exits 130 as every other does
    stopped = []

    def _interrupt(signum, frame):
        stopped.append(signum)
        raise KeyboardInterrupt
    previous = signal.signal(signal.SIGINT, _interrupt)
    try:
        app.run(host=host, port=port, debug=False, threaded=True)
    finally:
        signal.signal(signal.SIGINT, previous)
    if stopped:
        raise KeyboardInterrupt


def page_url(host: str, port: int) -> str:
    """The address a browser opens: an IPv6 address in brackets (RFC 3986),
    since a bare ``::1:8050`` is no URL."""
    return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"


def _terminate(signum, frame):
    raise SystemExit(128 + signum)


def check_address(host: str, port: int):
    """ParameterError, before anything is built, if the server could not listen there."""
    if not 0 < port < 65536:
        raise ParameterError(f"--port {port}: must be from 1 to 65535")
    try:
        infos = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except socket.gaierror as err:
        raise ParameterError(f"--host {host}: not an address of this machine ({err.strerror})") from None
    family, kind, proto, _, addr = infos[0]
    with socket.socket(family, kind, proto) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind(addr)
        except OSError as err:
            raise ParameterError(f"cannot listen on {host}:{port} ({err.strerror}); "
                                 "choose another --port or --host") from None
