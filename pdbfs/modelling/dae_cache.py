"""The compiled DAE of a rig kept on disk, so that a new process simulating
the same rig skips flattening and structural analysis (and their imports).

The key is the rig's declaration: every component's class (its qualified
name and MRO), its parameters (declarations and values), variables,
connectors and the plain data it keeps (a law's name, a segment count), its
path in the tree, the connections, and the text of every source file that
could change what compile() makes of them: the packages holding the
component classes and pdbfs's modelling compiler, with CasADi's version. A
change to any of them gives another key (at worst a rebuild).

Only rigs built entirely from pdbfs's own packages (pdbfs.components,
pdbfs.models, ...) are kept: a class of the user's could draw on code
outside its file, which no key here sees. Anything unexpected (an attribute
that is not plain data, an unreadable cache, a damaged entry) means no
cache, never a stale DAE.
"""
from __future__ import annotations

import hashlib
import pickle
import sys
from pathlib import Path

import casadi as ca

from pdbfs.files import cache_folder, whole

#: bump when the DAE's pickled form changes
FORMAT = 2
#: the Component attributes the key covers by other means (or that do not matter)
_INTERNAL = {"_name", "_parent", "_params", "_vars", "_connectors", "_children", "_connections",
             "_compiled", "_given", "_declaring", "_pending", "_inputs"}


class _NotPlain(Exception):
    pass


def _plain(v) -> str:
    """A deterministic text of plain data (numbers, text, CasADi expressions,
    and tuples, lists and dicts of them); anything else is _NotPlain."""
    if v is None or isinstance(v, (bool, int, float, str)):
        return f"{type(v).__name__}:{v!r}"
    if isinstance(v, ca.SX):
        return f"SX:{v}"
    if isinstance(v, (tuple, list)):
        return f"{type(v).__name__}[" + ",".join(_plain(x) for x in v) + "]"
    if isinstance(v, dict):
        return "dict{" + ",".join(f"{_plain(k)}={_plain(x)}" for k, x in v.items()) + "}"
    raise _NotPlain(type(v).__name__)


def _package_dir(module_name: str) -> Path | None:
    """The folder of the pdbfs package holding ``module_name``
    (pdbfs.components.x -> the pdbfs.components folder), or None outside pdbfs."""
    parts = module_name.split(".")
    if parts[0] != "pdbfs" or len(parts) < 2:
        return None
    pkg = sys.modules.get(".".join(parts[:2]))
    f = getattr(pkg, "__file__", None)
    if f is None:
        return None
    return Path(f).parent if Path(f).name == "__init__.py" else Path(f)


def _source_hash(where: Path) -> str:
    """The hash of every .py file's text under ``where`` (a package folder),
    read each time (about a millisecond): an edit in a running session counts,
    however soon after the last."""
    d = hashlib.sha256()
    for f in sorted(where.rglob("*.py")) if where.is_dir() else [where]:
        d.update(f"{f.relative_to(where.parent)}\0".encode() + f.read_bytes() + b"\0")
    return d.hexdigest()


def declaration_key(root) -> str | None:
    """The key of ``root``'s compiled DAE, or None when it cannot be keyed
    safely (a class from outside pdbfs, an attribute that is not plain data)."""
    from .connectors import Connector
    h = hashlib.sha256()
    folders = {Path(__file__).parent}               # the modelling compiler itself
    try:
        for comp in root.walk():
            h.update(f"component {comp.path()}\0".encode())
            for cls in type(comp).__mro__[:-1]:
                where = _package_dir(cls.__module__)
                if where is None:
                    return None
                folders.add(where)
                h.update(f"{cls.__module__}.{cls.__qualname__}\0".encode())
            for name, slot in comp._params.items():
                h.update(f"param {name} {_plain(vars(slot.decl))} {_plain(slot.value)}\0".encode())
            for name, slot in comp._vars.items():
                h.update(f"var {name} {type(slot.decl).__name__} "
                         f"{_plain(vars(slot.decl))}\0".encode())
            for name, slot in comp._inputs.items():
                h.update(f"input {name} {_plain(vars(slot.decl))}\0".encode())
            for name, c in comp._connectors.items():
                data = {k: v for k, v in vars(c).items() if k not in ("owner", "name")
                        and not isinstance(v, ca.SX)}
                h.update(f"connector {name} {type(c).__name__} {_plain(data)}\0".encode())
            for conn in comp._connections:
                h.update(("connect " + " ".join(c.path() for c in conn) + "\0").encode())
            for k, v in sorted(vars(comp).items()):
                if k in _INTERNAL or k in comp._params or k in comp._vars or \
                        isinstance(v, Connector) or v is comp._children.get(k):
                    continue
                h.update(f"attr {k} {_plain(v)}\0".encode())
        h.update(f"casadi {ca.__version__} format {FORMAT}\0".encode())
        for where in sorted(folders):
            h.update(f"{where.name} {_source_hash(where)}\0".encode())
    except (_NotPlain, OSError):
        return None
    return h.hexdigest()[:32]


def _cache_dir() -> Path:
    return cache_folder() / "dae"


def load(key: str):
    """The DAE kept under ``key``, or None (absent, unreadable or damaged)."""
    try:
        data = (_cache_dir() / f"{key}.pkl").read_bytes()
        with ca.global_unpickle_context():
            dae = pickle.loads(data)
    except Exception:            # noqa: BLE001 -- a damaged entry is rebuilt, never trusted
        return None
    return dae if type(dae).__name__ == "DAE" else None


def store(key: str, dae) -> None:
    """Keep ``dae`` under ``key`` (atomically; a cache that cannot be written
    is no error)."""
    try:
        with ca.global_pickle_context():
            data = pickle.dumps(dae, protocol=pickle.HIGHEST_PROTOCOL)
        folder = _cache_dir()
        folder.mkdir(parents=True, exist_ok=True)
        with whole(folder / f"{key}.pkl") as part:
            part.write_bytes(data)
    except Exception:            # noqa: BLE001 -- no cache, nothing worse
        return
