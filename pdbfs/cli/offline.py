"""pdbfs prepare-offline: everything pdbfs fetches or builds once, done now
(SUNDIALS' sources through pip's index, CVODE compiled for every FMU
platform), and how to carry it to a machine without network."""
from __future__ import annotations

import shutil
import sys

from pdbfs.files import whole

from .common import prepare_out


def _size(folder) -> float:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file()) / 1e6


def cmd_prepare_offline(args):
    """pdbfs prepare-offline: fetch the sources, build CVODE, say how to carry the cache."""
    from pdbfs.fmu.platforms import prepare_offline
    out = prepare_out(args.out) if args.out else None

    def say(k, n, text):
        print(f"pdbfs: [{k}/{n}] {text}", file=sys.stderr, flush=True)
    done = prepare_offline(args.platforms, say)
    cache, sdist = done["cache"], done["sdist"]
    print(f"pdbfs's cache {cache} is ready for offline work ({_size(cache):.0f} MB): "
          f"{done['sources']}; CVODE built for {', '.join(done['platforms']) or 'no platform'}")
    if out is not None and sdist is not None:
        out.mkdir(parents=True, exist_ok=True)
        with whole(out / sdist.name) as part:
            shutil.copyfile(sdist, part)
        sdist = out / sdist.name
        print(f"wrote {sdist}")
    print("To work on a machine without network, either")
    print(f"  copy the folder {cache} to pdbfs's cache folder there (the same path under the "
          "user's home on Linux: $XDG_CACHE_HOME/pdbfs, default ~/.cache/pdbfs; print it with "
          "python -c \"import pdbfs.files as f; print(f.cache_folder())\"), or")
    print(f"  copy {sdist or 'the sdist PDBFS_SUNDIALS_SDIST named'} there and set "
          "PDBFS_SUNDIALS_SDIST to its path (CVODE is then compiled there, once per platform).")
    return 0


def add_parsers(sub):
    """Add the ``prepare-offline`` command to the subparsers ``sub``."""
    s = sub.add_parser(
        "prepare-offline",
        help="fetch SUNDIALS' sources and compile CVODE for every platform now, for work "
        "without network",
        description="Fetch SUNDIALS' sources (the sdist amici-1.1.0.tar.gz, through the package "
        "index pip is configured with: PIP_INDEX_URL, PIP_EXTRA_INDEX_URL, pip.conf) and compile "
        "CVODE for each FMU platform into pdbfs's cache, then say how to carry them to a machine "
        "without network. The sources can also be given as a file: PDBFS_SUNDIALS_SDIST=PATH.")
    s.add_argument("--platforms", default="all", metavar="P1,P2",
                   help="platforms to compile CVODE for: x86_64-linux, aarch64-linux, "
                   "x86_64-windows, x86_64-darwin, aarch64-darwin, all, or none (the sources "
                   "only) (default: all)")
    s.add_argument("--out", default=None, metavar="DIR",
                   help="also copy the sdist to DIR, to carry it (default: none)")
    s.set_defaults(func=cmd_prepare_offline)
