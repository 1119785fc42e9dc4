"""Every public object a user can reach carries a docstring, and the public
API's functions carry type hints.

- Public objects: every module of pdbfs (its subpackages, the component
  library, the rigs, the FMU exporter and the studies included); the classes
  and functions a module defines whose names do not start with "_"; the
  public methods and properties a public class defines itself (dunder
  methods aside). An override of a documented pdbfs method inherits that
  method's docstring, as ``inspect.getdoc`` and ``help()`` show it.
- Type hints: the functions, and the public methods of the classes, that
  pdbfs, pdbfs.simulation, pdbfs.studies, pdbfs.fmu, pdbfs.components and
  pdbfs.models export in ``__all__`` annotate every parameter and the return
  (``__init__`` its parameters). An override with the parameters of a
  pdbfs method it overrides (a component's ``declare``, ``equations``) has
  that method's hints. The Simulator, which pdbfs.simulation exports for the
  studies and the workbench rather than for users, is left out.
"""
from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

#: the packages whose modules are walked (pdbfs.components, .models and .fmu
#: live outside pdbfs/ on disk, so pdbfs's own walk does not find them)
ROOTS = ("pdbfs", "pdbfs.components", "pdbfs.models", "pdbfs.fmu")
#: the packages whose ``__all__`` is the typed public API
TYPED = ("pdbfs", "pdbfs.simulation", "pdbfs.studies", "pdbfs.fmu", "pdbfs.components",
         "pdbfs.models")
#: exported for the layers above, not for users (see the module docstring)
INTERNAL = {"Simulator"}


def modules() -> list:
    """Every module under ROOTS, imported (``__main__`` aside: it runs the CLI)."""
    found = {}
    for root in ROOTS:
        pkg = importlib.import_module(root)
        found[root] = pkg
        for info in pkgutil.walk_packages(pkg.__path__, root + "."):
            if info.name.rsplit(".", 1)[-1] == "__main__":
                continue
            found[info.name] = importlib.import_module(info.name)
    return [found[k] for k in sorted(found)]


def _public(name: str) -> bool:
    return not name.startswith("_")


def _function_of(member):
    """The function behind a class member (method, static/class method,
    property or cached property), or None for a plain attribute."""
    if isinstance(member, (staticmethod, classmethod)):
        return member.__func__
    if isinstance(member, property):
        return member.fget
    if inspect.isfunction(member):
        return member
    func = getattr(member, "func", None)        # functools.cached_property
    return func if inspect.isfunction(func) else None


def _inherited_doc(cls, name: str):
    """The docstring of the member ``name`` of cls's pdbfs bases, if any."""
    for base in cls.__mro__[1:]:
        if name in vars(base) and base.__module__.startswith("pdbfs"):
            func = _function_of(vars(base)[name])
            if func is not None and inspect.getdoc(func):
                return inspect.getdoc(func)
    return None


def _class_doc(cls) -> str:
    """cls's own docstring; the one a dataclass, a NamedTuple or an Enum is
    given by Python (its name and fields) is none."""
    doc = (cls.__doc__ or "").strip()
    made = doc.startswith(cls.__name__ + "(") and doc.endswith(")") and "\n" not in doc
    return "" if made or doc == "An enumeration." else doc


def undocumented() -> list[str]:
    """The dotted names of the public objects without a docstring."""
    missing = []
    for mod in modules():
        if not (mod.__doc__ or "").strip():
            missing.append(mod.__name__)
        for name, obj in vars(mod).items():
            if not _public(name) or getattr(obj, "__module__", None) != mod.__name__:
                continue
            if not (inspect.isclass(obj) or inspect.isfunction(obj)):
                continue
            if not (_class_doc(obj) if inspect.isclass(obj) else (obj.__doc__ or "").strip()):
                missing.append(f"{mod.__name__}.{name}")
            if inspect.isclass(obj):
                missing += [f"{mod.__name__}.{name}.{m}" for m in _undocumented_members(obj)]
    return missing


def _undocumented_members(cls) -> list[str]:
    out = []
    for name, member in vars(cls).items():
        if not _public(name):
            continue
        func = _function_of(member)
        if func is None or (func.__doc__ or "").strip():
            continue
        if _inherited_doc(cls, name) is None:
            out.append(name)
    return out


def test_every_public_object_has_a_docstring():
    missing = undocumented()
    assert not missing, f"{len(missing)} public objects without a docstring:\n  " + "\n  ".join(missing)


def test_the_walk_sees_the_library():
    """The walk reaches the packages users import, so a count of zero means something."""
    import pdbfs
    from pdbfs.studies import Calibration, SweepResult
    names = {m.__name__ for m in modules()}
    assert {"pdbfs.rig", "pdbfs.components.translational.contact", "pdbfs.cli", "pdbfs.app",
            "pdbfs.components.hydraulic.volume", "pdbfs.models.paper", "pdbfs.fmu.export"} <= names
    assert {c.__module__ for c in (pdbfs.Result, SweepResult, Calibration)} <= names
    assert len(names) > 100


def public_api() -> list[tuple[str, object]]:
    """(dotted name, function) of the typed public API: the functions in the
    ``__all__`` of TYPED, and the public methods the classes there define."""
    out = {}
    for pkg_name in TYPED:
        pkg = importlib.import_module(pkg_name)
        for name in pkg.__all__:
            if name in INTERNAL:
                continue
            obj = getattr(pkg, name)
            if inspect.isfunction(obj):
                out[f"{obj.__module__}.{obj.__qualname__}"] = (obj, None)
            elif inspect.isclass(obj) and obj.__module__.startswith("pdbfs"):
                for m, member in vars(obj).items():
                    func = _function_of(member)
                    if func is not None and (_public(m) or m == "__init__"):
                        out[f"{obj.__module__}.{func.__qualname__}"] = (func, obj)
    return sorted(out.items())


def _hints(func) -> tuple[list, bool]:
    """(parameters without a hint, whether the return has one); self and cls aside."""
    sig = inspect.signature(func)
    params = [p for p in sig.parameters.values() if p.name not in ("self", "cls")]
    return ([p.name for p in params if p.annotation is inspect.Parameter.empty],
            sig.return_annotation is not inspect.Signature.empty)


def _unhinted(func, cls=None) -> list[str]:
    """The parameters (and "return") of func without a type hint; a method of
    cls overriding a pdbfs method with the same parameters counts its hints."""
    missing, returns = _hints(func)
    names = list(inspect.signature(func).parameters)
    for base in (cls.__mro__[1:] if cls is not None and func.__name__ != "__init__" else ()):
        over = _function_of(vars(base).get(func.__name__))
        if over is not None and base.__module__.startswith("pdbfs") \
                and list(inspect.signature(over).parameters) == names:
            base_missing, base_returns = _hints(over)
            missing = [m for m in missing if m in base_missing]
            returns = returns or base_returns
    return missing + ([] if returns or func.__name__ == "__init__" else ["return"])


def test_the_public_api_has_type_hints():
    api = public_api()
    assert len(api) > 50
    bare = [f"{name}: {', '.join(m)}" for name, (func, cls) in api if (m := _unhinted(func, cls))]
    assert not bare, f"{len(bare)} public functions without full type hints:\n  " + "\n  ".join(bare)


@pytest.mark.parametrize("method", ["simulate", "linearize", "export_fmu"])
def test_rig_methods_show_their_arguments(method):
    """Rig.simulate, Rig.linearize and Rig.export_fmu list the keyword
    arguments of the functions they call, with the same defaults."""
    from pdbfs import Rig
    from pdbfs.fmu import export_fmu
    from pdbfs.simulation import linearize, simulate
    target = {"simulate": simulate, "linearize": linearize, "export_fmu": export_fmu}[method]
    own = inspect.signature(getattr(Rig, method)).parameters
    assert not any(p.kind is p.VAR_KEYWORD for p in own.values()), f"Rig.{method} takes **kwargs"
    # the first parameter of the function is the rig (or its DAE); the rig's
    # experiment fills export_fmu's stop_time and step_size when not given
    theirs = list(inspect.signature(target).parameters.values())[1:]
    for p in theirs:
        assert p.name in own, f"Rig.{method} lacks {p.name}"
        if method == "export_fmu" and p.name in ("stop_time", "step_size"):
            assert own[p.name].default is None
            continue
        assert own[p.name].default == p.default, (p.name, own[p.name].default, p.default)
    assert "Parameters" in inspect.getdoc(getattr(Rig, method))
