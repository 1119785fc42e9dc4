"""pdbfs app: the rig workbench in the browser, served on this machine."""
from __future__ import annotations

from pdbfs.errors import require_extra


def cmd_app(args):
    """pdbfs app: serve the workbench page until Ctrl-C."""
    require_extra("app", "pdbfs app")
    from pdbfs.app import serve
    serve(args.rig, host=args.host, port=args.port, open_browser=args.open,
          ready=lambda url: print(f"pdbfs workbench of rig {args.rig} at {url} "
                                  "(Ctrl-C stops it)", flush=True))


def add_parsers(sub):
    """Add the ``app`` command to the subparsers ``sub``."""
    s = sub.add_parser("app", help="serve the rig workbench (a page in the browser)")
    s.add_argument("--rig", default="paper", metavar="RIG",
                   help="rig shown first: a name of `pdbfs rigs` (default: paper), or a rig of your "
                   "own, FILE.py:NAME or MODULE:NAME (offered beside the shipped ones)")
    s.add_argument("--port", type=int, default=8050, help="port (default 8050)")
    s.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1: this machine only)")
    s.add_argument("--open", action="store_true", help="open the page in a browser")
    s.set_defaults(func=cmd_app)
