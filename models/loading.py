"""A user's own rig, named by where it is defined: ``FILE.py:NAME`` or
``MODULE:NAME`` (what ``--rig`` takes, beside the names of RIGS, in every
command and in the workbench; :func:`pdbfs.models.rig_from`).

NAME is a Rig subclass (built with no arguments) or a function returning
a rig: each use builds a new one. Everything that can go wrong in finding
and building it (no such file or module, an error in the file, no such
name, something that is not a rig, a builder that raises) is a
ParameterError of one line naming the culprit, raised before any work.
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.util
import inspect
import os
import sys
from pathlib import Path

from pdbfs.errors import ParameterError, PdbfsError
from pdbfs.rig import Rig

#: what a user's rig is given as (shown in messages)
FORMS = "FILE.py:NAME or MODULE:NAME (NAME a Rig class or a function returning a rig)"


def user_rig(spec: str, where: str, names) -> Rig:
    """A new rig of the user's, built as ``spec`` (``FILE.py:NAME`` or
    ``MODULE:NAME``) says, or a ParameterError of one line naming what is
    wrong: :func:`pdbfs.models.rig_from` for a name that is not a shipped one.

    Parameters
    ----------
    spec : str
        Where the rig is defined and its name there.
    where : str
        What gave ``spec``, as messages name it.
    names : sequence of str
        The shipped rigs' names, offered by the message of an unknown name.
    """
    if not isinstance(spec, str) or not spec.strip():
        raise ParameterError(f"{where} {spec!r}: give a rig name ({', '.join(names)}) or {FORMS}")
    head, colon, name = spec.rpartition(":")
    if not colon or not _is_name(name):         # no :NAME (or a Windows drive's colon)
        head, name = spec, ""
    shown = f"{where} {spec}"
    if not _is_file(head):
        if not name:
            raise ParameterError(f"unknown rig {spec!r}; choose one of {', '.join(names)}, or "
                                 f"give {FORMS}")
        module = _import_module(head, shown)
    else:
        module = _import_file(Path(head), shown)
    if not name:
        name = _only_rig_class(module, shown)
    return _build(module, name, shown)


def first_paragraph(build, rig: Rig) -> str:
    """The first paragraph of ``build``'s docstring in one line (a lambda's:
    of ``rig``'s class's).

    Parameters
    ----------
    build : callable or None
        What built the rig (None: a rig of the user's).
    rig : Rig
        The rig it built.
    """
    doc = build.__doc__ if build is not None and build.__name__ != "<lambda>" else None
    doc = doc or type(rig).__doc__
    return " ".join(inspect.cleandoc(doc or "").split("\n\n")[0].split())


# -- finding the module ---------------------------------------------------------------
def _is_name(text: str) -> bool:
    return bool(text) and all(part.isidentifier() for part in text.split("."))


def _is_file(head: str) -> bool:
    return head.endswith(".py") or "/" in head or os.sep in head


def _import_file(path: Path, shown: str):
    """The module of the file ``path``, imported once per process."""
    if not path.is_file():
        raise ParameterError(f"{shown}: no such file {path}" if not path.is_dir() else
                             f"{shown}: {path} is a folder; name a .py file")
    path = path.resolve()
    key = "pdbfs_user_rig_" + hashlib.sha1(str(path).encode()).hexdigest()[:12]
    if key in sys.modules:
        return sys.modules[key]
    spec = importlib.util.spec_from_file_location(key, path)
    if spec is None or spec.loader is None:
        raise ParameterError(f"{shown}: {path} cannot be imported as Python (name it NAME.py)")
    module = importlib.util.module_from_spec(spec)
    folder = str(path.parent)
    if folder not in sys.path:           # as `python FILE.py` does: its neighbours import
        sys.path.insert(0, folder)
    sys.modules[key] = module            # (dataclasses and pickling look the module up)
    try:
        spec.loader.exec_module(module)
    except BaseException as err:
        del sys.modules[key]
        if isinstance(err, KeyboardInterrupt):
            raise
        raise ParameterError(f"{shown}: {_failure(err, path, 'importing ' + path.name)}") from None
    return module


def _import_module(name: str, shown: str):
    if "" not in sys.path and os.getcwd() not in sys.path:
        sys.path.append(os.getcwd())     # a module in the current folder, as `python -m` finds it
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as err:
        if err.name is not None and (name == err.name or name.startswith(err.name + ".")):
            raise ParameterError(f"{shown}: no module named {err.name!r} (nor a file {name!r}; "
                                 "a file's name ends in .py)") from None
        raise ParameterError(f"{shown}: {_failure(err, None, 'importing ' + name)}") from None
    except KeyboardInterrupt:
        raise
    except BaseException as err:
        raise ParameterError(f"{shown}: {_failure(err, None, 'importing ' + name)}") from None


def _failure(err: BaseException, path: Path | None, doing: str) -> str:
    """What went wrong, where: the error and the line of the user's code."""
    if isinstance(err, SyntaxError) and not isinstance(err, PdbfsError):
        where = Path(err.filename).name if err.filename else "the file"
        return f"{doing} failed: {where} line {err.lineno}: {err.msg}"
    line = _user_line(err, path)
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    what = text if isinstance(err, PdbfsError) else \
        f"{type(err).__name__}" + (f": {text}" if text else "")
    return f"{doing} failed: {what}" + (f" ({line})" if line else "")


def _user_line(err: BaseException, path: Path | None) -> str:
    """``FILE line N``: the deepest frame of the traceback outside pdbfs
    (in ``path`` when given), or ''."""
    import traceback
    here = Path(__file__).resolve().parents[1]
    frames = traceback.extract_tb(err.__traceback__)
    inside = [f for f in frames if (path is not None and Path(f.filename) == path) or
              (path is None and not f.filename.startswith(str(here)) and "importlib" not in f.filename
               and not f.filename.startswith("<"))]
    if not inside:
        return ""
    f = inside[-1]
    return f"{Path(f.filename).name} line {f.lineno}"


# -- the name in it -------------------------------------------------------------------
def _rig_classes(module) -> list[str]:
    """The Rig subclasses ``module`` defines (not those it imports)."""
    return [n for n, v in vars(module).items() if inspect.isclass(v) and issubclass(v, Rig)
            and v is not Rig and v.__module__ == module.__name__]


def _only_rig_class(module, shown: str) -> str:
    classes = _rig_classes(module)
    if len(classes) == 1:
        return classes[0]
    found = f"it defines {', '.join(classes)}" if classes else "it defines no Rig class"
    raise ParameterError(f"{shown}: name the rig as FILE.py:NAME ({found})")


def _build(module, name: str, shown: str) -> Rig:
    obj = module
    for part in name.split("."):
        if not hasattr(obj, part):
            classes = _rig_classes(module)
            have = f" (its Rig classes: {', '.join(classes)})" if classes else ""
            raise ParameterError(f"{shown}: {_module_name(module)} has no {name!r}{have}")
        obj = getattr(obj, part)
    if isinstance(obj, Rig):
        raise ParameterError(f"{shown}: {name} is a rig, built once; name its class "
                             f"({type(obj).__name__}) or a function that builds one")
    if inspect.isclass(obj) and not issubclass(obj, Rig):
        raise ParameterError(f"{shown}: {name} is the class {obj.__name__}, not a Rig subclass"
                             " (a component goes into a rig: see pdbfs.Rig)")
    if not callable(obj):
        raise ParameterError(f"{shown}: {name} is {_what(obj)}, not a Rig class or a function "
                             "returning a rig")
    path = Path(module.__file__).resolve() if getattr(module, "__file__", None) else None
    try:
        rig = obj()
    except KeyboardInterrupt:
        raise
    except BaseException as err:
        raise ParameterError(f"{shown}: {_failure(err, path, name + '()')}") from None
    if not isinstance(rig, Rig):
        raise ParameterError(f"{shown}: {name}() returned {_what(rig)}, not a rig")
    return rig


def _what(obj) -> str:
    text = repr(obj)
    return f"the {type(obj).__name__} {text if len(text) <= 40 else text[:37] + '...'}"


def _module_name(module) -> str:
    file = getattr(module, "__file__", None)
    return Path(file).name if file and module.__name__.startswith("pdbfs_user_rig_") \
        else module.__name__
