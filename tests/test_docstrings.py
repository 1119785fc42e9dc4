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
- The reference (what the API pages render, and the ``__all__`` of the
  packages users import, as ``help()`` shows them; the Simulator and the
  checks pdbfs.fmu exports for the layers above aside): each public
  callable with arguments has a NumPy ``Parameters`` section that lists
  every named argument and no other, and a ``Returns`` section if it
  returns a value (``argument_problems`` says the rules of components and
  of the result classes);
  the entry points a user calls first have an ``Examples`` section, and
  every Examples section of the reference runs as a doctest; no docstring of
  the reference names a file of the repository (``scripts/``, ``tests/``, a
  source file, ``../shared``), and no docstring at all names one a wheel
  does not hold.
"""
from __future__ import annotations

import doctest
import importlib
import inspect
import pkgutil
import re
from pathlib import Path

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


# --- the reference: sections, examples, paths ---------------------------------------------

#: the packages whose ``__all__`` the API reference documents
REFERENCE = ("pdbfs", "pdbfs.components", "pdbfs.components.translational",
             "pdbfs.components.hydraulic", "pdbfs.components.thermal", "pdbfs.components.blocks",
             "pdbfs.models", "pdbfs.fmu", "pdbfs.studies", "pdbfs.fatigue", "pdbfs.simulation")
API_PAGES = Path(__file__).resolve().parents[1] / "docs" / "reference" / "api"
#: classes pdbfs makes and hands to users (a run's, a study's or the compiler's
#: result), never built by them: their docstring's ``Attributes`` section says
#: what they hold, in place of a Parameters section of their constructor
RESULTS = {"Result", "SweepResult", "SweepPoint", "Calibration", "Design", "DesignMap",
           "Sensitivity", "Linearization", "HeightSearch", "CoSimulation", "DAE", "ParamInfo",
           "VarInfo", "CampaignResult", "HeatNetwork", "Schedule"}
#: what pdbfs.fmu exports for Rig.export_fmu and the command line to check before a
#: rig is compiled, not for users (the API pages do not show them), as the Simulator
CHECKS_FOR_THE_LAYERS_ABOVE = {"check_fmi_version", "check_fmu_name", "check_rights",
                               "check_experiment"}
#: the entry points a user calls first: each shows a runnable example (an FMU's:
#: Rig.export_fmu, which calls pdbfs.fmu.export_fmu with the rig's experiment)
ENTRY_POINTS = (
    "pdbfs.simulate", "pdbfs.Rig.simulate", "pdbfs.Rig.linearize", "pdbfs.Rig.export_fmu",
    "pdbfs.fmu.export_ssp", "pdbfs.sweep", "pdbfs.sensitivity", "pdbfs.calibrate", "pdbfs.design",
    "pdbfs.design_map", "pdbfs.Result", "pdbfs.Result.value_at", "pdbfs.Result.peak",
    "pdbfs.Result.crossings", "pdbfs.Result.summary", "pdbfs.studies.SweepResult",
    "pdbfs.studies.SweepResult.values", "pdbfs.studies.SweepResult.table",
    "pdbfs.studies.SweepResult.to_pandas", "pdbfs.studies.SweepResult.points",
    "pdbfs.studies.SweepResult.load")
#: a repository path: its own folders (the docs' sources too: the site has the pages,
#: not their files), the shared notes, or a Python file (a source file is one if the
#: repository has a file of that name: ``FILE.py`` standing for a user's own is not)
REPOSITORY_PATH = re.compile(r"\b(?:scripts|tests|docs)/|\.\./shared|(?<![\w.])[\w/]+\.py\b")
#: the repository's Python files, by name
REPOSITORY_FILES = {p.name for d in ("pdbfs", "components", "models", "fmu", "scripts", "tests", "docs")
                    for p in (API_PAGES.parents[2] / d).rglob("*.py")}
#: what a wheel does not hold at all (internal modules may name their neighbours)
NOT_IN_WHEEL = re.compile(r"\b(?:scripts|tests|docs)/|\.\./shared|\btest_\w+\.py\b")


def _resolve(dotted: str):
    """The object a dotted name (``pdbfs.studies.Sweep.values``) names."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attr in parts[i:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(dotted)


def _module_members(mod) -> dict[str, object]:
    """What an API page's ``::: module`` shows: its ``__all__``, and the public
    classes and functions it defines."""
    names = list(getattr(mod, "__all__", []))
    names += [n for n, o in vars(mod).items() if _public(n) and getattr(o, "__module__", None)
              == mod.__name__ and (inspect.isclass(o) or inspect.isfunction(o))]
    return {f"{mod.__name__}.{n}": getattr(mod, n) for n in dict.fromkeys(names)}


def reference() -> dict[str, object]:
    """Dotted name -> object of the reference's classes and functions: the
    ``__all__`` of REFERENCE and what the API pages' directives name (a
    module: its members), each once (under its first name)."""
    found: dict[str, object] = {}
    for pkg_name in REFERENCE:
        pkg = importlib.import_module(pkg_name)
        found.update({f"{pkg_name}.{n}": getattr(pkg, n) for n in pkg.__all__})
    for page in sorted(API_PAGES.glob("*.md")):
        for line in page.read_text().splitlines():
            if line.startswith("::: "):
                obj = _resolve(line[4:].strip())
                found.update(_module_members(obj) if inspect.ismodule(obj) else {line[4:].strip(): obj})
    seen, out = set(), {}
    for name, obj in found.items():
        short = name.rsplit(".", 1)[-1]
        if (inspect.isclass(obj) or inspect.isfunction(obj)) and short not in INTERNAL \
                and short not in CHECKS_FOR_THE_LAYERS_ABOVE \
                and obj.__module__.startswith("pdbfs") and id(obj) not in seen:
            seen.add(id(obj))
            out[name] = obj
    return out


def reference_callables() -> list[tuple[str, object, object]]:
    """(dotted name, function or class, its class or None) of the reference:
    its classes and functions, and the public methods and properties its
    classes define themselves or take from a pdbfs base outside the
    reference (Result's exports), which their page shows with them."""
    out = []
    ref = reference()
    classes = {id(o) for o in ref.values() if inspect.isclass(o)}
    for name, obj in ref.items():
        out.append((name, obj, None))
        if inspect.isclass(obj):
            own = [k for k in obj.__mro__ if k is obj or (k.__module__.startswith("pdbfs")
                                                          and id(k) not in classes)]
            members = {}
            for k in reversed(own):
                members.update(vars(k))
            for m, member in members.items():
                func = _function_of(member)
                if func is not None and _public(m):
                    out.append((f"{name}.{m}", func, obj))
    return out


def _doc_of(obj, cls=None) -> str:
    """The docstring help() shows: a class's own, a method's own or its pdbfs base's."""
    if inspect.isclass(obj):
        return inspect.cleandoc(_class_doc(obj))
    return inspect.cleandoc(obj.__doc__ or "") or (_inherited_doc(cls, obj.__name__) or "" if cls else "")


#: a NumPy section's heading: a title, then a line of dashes as long
SECTION = re.compile(r"^([A-Z][A-Za-z ]+)\n(-{3,})[ \t]*$", re.M)


def sections(doc: str) -> dict[str, str]:
    """A NumPy docstring's sections: heading -> body."""
    heads = list(SECTION.finditer(doc))
    return {h.group(1): doc[h.end():heads[i + 1].start() if i + 1 < len(heads) else len(doc)]
            for i, h in enumerate(heads)}


def entries(body: str) -> list[str]:
    """The names a Parameters (or Attributes) section lists: its unindented
    lines' names before the colon (``a, b : float`` lists two)."""
    names = []
    for line in body.splitlines():
        if line.strip() and not line[0].isspace():
            names += [n.strip() for n in line.split(" : ")[0].split(",")]
    return names


def _arguments(obj) -> tuple[list[str], list[str]]:
    """(named arguments, ``*args``/``**kwargs`` names) of a callable, self and cls aside."""
    try:
        params = inspect.signature(obj).parameters.values()
    except (TypeError, ValueError):     # an exception class: its arguments are Python's
        return [], []
    var = [("*" if p.kind is p.VAR_POSITIONAL else "**") + p.name for p in params
           if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    return [p.name for p in params if p.name not in ("self", "cls") and p.kind not in
            (p.VAR_POSITIONAL, p.VAR_KEYWORD)], var


def _is_component(obj) -> bool:
    from pdbfs import Component
    return inspect.isclass(obj) and issubclass(obj, Component)


def _instance_attributes(cls) -> set[str]:
    """The attributes a class's methods (its pdbfs bases' too) set on ``self``."""
    return {m for k in cls.__mro__ if k.__module__.startswith("pdbfs")
            for m in re.findall(r"\bself\.(\w+)", inspect.getsource(k))}


def _returns_a_value(func) -> bool:
    """Whether a function's return annotation is one of a value (not None)."""
    ann = inspect.signature(func).return_annotation
    return ann not in (None, "None", inspect.Signature.empty)


def argument_problems(name: str, obj, cls=None) -> list[str]:
    """What a callable's Parameters section gets wrong about its arguments.

    - A function or method with named arguments lists each, and lists
      nothing its signature lacks (``*args``/``**kwargs`` by that name);
      if it returns a value, it has a Returns (or Yields) section too.
    - A class: its constructor's arguments, likewise. A component (a rig
      too) takes its declared Parameter values as keywords, which the
      component catalogue and the rigs page list: its section lists its
      other constructor arguments (its options: ``law=``, ``heat_port=``,
      sizes), and may list declared parameters. A class of RESULTS has an
      ``Attributes`` section, each entry an attribute it has.
    - A set of choices (``{"auto", "bdf"}``) begins with the default.
    """
    doc = _doc_of(obj, cls)
    secs = sections(doc)
    named, var = _arguments(obj)
    if inspect.isclass(obj) and obj.__name__ in RESULTS:
        if "Attributes" not in secs:
            return [f"{name}: no Attributes section"]
        fields = set(getattr(obj, "__dataclass_fields__", {})) | set(dir(obj)) | set(named) \
            | _instance_attributes(obj)
        bad = [e for e in entries(secs["Attributes"]) if e not in fields]
        return [f"{name}: Attributes lists {bad}, which it does not have"] if bad else []
    if not named:
        return []
    if "Parameters" not in secs:
        return [f"{name}: no Parameters section (arguments {named})"]
    listed = entries(secs["Parameters"])
    allowed = set(named) | set(var) | {v.lstrip("*") for v in var}
    if _is_component(obj):
        allowed |= {n for k in obj.__mro__ for n, d in vars(k).items()
                    if type(d).__name__ == "Parameter"}
    out = []
    if not inspect.isclass(obj) and _returns_a_value(obj) and "Returns" not in secs \
            and "Yields" not in secs:
        out.append(f"{name}: no Returns section")
    if missing := [n for n in named if n not in listed]:
        out.append(f"{name}: Parameters misses {missing}")
    if extra := [n for n in listed if n not in allowed]:
        out.append(f"{name}: Parameters lists {extra}, which it does not take")
    return out + _choice_problems(name, obj, secs["Parameters"])


#: a Parameters entry whose type is a set of choices: ``method : {"auto", "bdf"}``
CHOICES = re.compile(r"^(\w+) : \{(.+)\}", re.M)


def _choice_problems(name: str, obj, body: str) -> list[str]:
    """A set of choices whose first is not the argument's default: the API
    pages show the first choice as the default (NumPy's convention), so an
    argument whose default is None (or another value), or that has none,
    says its choices otherwise."""
    import ast
    params = inspect.signature(obj).parameters
    out = []
    for arg, choices in CHOICES.findall(body):
        p = params.get(arg)
        if p is None:
            continue
        if p.default is inspect.Parameter.empty:
            out.append(f"{name}: {arg} is required, but its choices show a default")
            continue
        try:
            first = ast.literal_eval(choices.split(",")[0].strip())
        except (ValueError, SyntaxError):
            first = choices.split(",")[0].strip()
        if first != p.default:
            out.append(f"{name}: {arg}'s choices begin with {first!r}, its default is {p.default!r}")
    return out


def test_public_callables_list_their_arguments():
    found = reference_callables()
    assert len(found) > 400
    bad = [p for name, obj, cls in found for p in argument_problems(name, obj, cls)]
    assert not bad, f"{len(bad)} problems:\n  " + "\n  ".join(bad)


def test_the_section_reader_reads_a_numpy_docstring():
    """The rules above read sections as mkdocstrings does: a check that
    could pass on any text would prove nothing."""
    from pdbfs.fatigue import SNCurve
    secs = sections(_doc_of(SNCurve))
    assert list(secs) == ["Parameters", "Raises", "Examples"]
    assert entries(secs["Parameters"]) == ["m", "stress_range_ref", "cycles_ref", "endurance_limit"]
    assert entries("x, y : float\n    Two.\n**params\n    More.\n") == ["x", "y", "**params"]

    def f(a, b, *, c=1, **kw) -> float:
        """F.

        Parameters
        ----------
        a : float
            A.
        d : int
            Not an argument.
        """
    def g(method="bdf", law=None):
        """G.

        Parameters
        ----------
        method : {"auto", "bdf"}
            M.
        law : {"a", "b"}, optional
            L.
        """
    assert argument_problems("g", g) == ["g: method's choices begin with 'auto', its default is 'bdf'",
                                         "g: law's choices begin with 'a', its default is None"]
    assert argument_problems("f", f) == ["f: no Returns section",
                                         "f: Parameters misses ['b', 'c']",
                                         "f: Parameters lists ['d'], which it does not take"]


def _connectors(cls) -> list[str] | None:
    """A component's connectors, or None if it cannot be built without arguments."""
    try:
        return list(cls()._connectors)
    except Exception:  # noqa: BLE001 - a size or a table to give first
        return None


def component_classes() -> list[tuple[str, type]]:
    """The concrete components of the library (partial bases and rigs aside)."""
    from pdbfs import Rig
    return [(n, c) for n, c in reference().items() if _is_component(c) and not issubclass(c, Rig)
            and n.startswith("pdbfs.components") and not c.__name__.startswith("Partial")]


def test_every_component_names_its_connectors():
    """A component's description names each connector it has (``flange_a``,
    ``port``, ``u``, ``y``, ``heat_port``), so its page says how to connect it."""
    comps = component_classes()
    assert len(comps) > 60
    bad = []
    for name, cls in comps:
        conns = _connectors(cls)
        doc = _doc_of(cls)
        bad += [f"{name}: {c}" for c in conns or () if not re.search(rf"\b{c}\b", doc)]
    assert not bad, f"{len(bad)} connectors no description names:\n  " + "\n  ".join(bad)


@pytest.mark.parametrize("name", ENTRY_POINTS)
def test_entry_points_have_examples(name):
    obj = _resolve(name)
    func = obj.__func__ if inspect.ismethod(obj) else obj if inspect.isclass(obj) or \
        inspect.isfunction(obj) else _function_of(obj)
    assert func is not None, f"{name} is no function, class or property"
    doc = _doc_of(func)
    assert "Examples" in sections(doc), f"{name} has no Examples section"
    assert ">>> " in sections(doc)["Examples"], f"{name}'s Examples has no code to run"


def examples() -> list[tuple[str, object]]:
    """(dotted name, the object) of every callable of the reference whose
    docstring has an Examples section."""
    return [(n, (obj, cls)) for n, obj, cls in reference_callables()
            if "Examples" in sections(_doc_of(obj, cls))]


@pytest.mark.parametrize("name,obj", examples(), ids=[n for n, _ in examples()])
def test_the_examples_run(name, obj):
    """Each Examples section runs as a doctest and prints what it shows."""
    func, _ = obj
    text = sections(_doc_of(func))["Examples"]
    parser = doctest.DocTestParser()
    test = parser.get_doctest(text, {}, name, None, 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    out = []
    runner.run(test, out=out.append)
    assert test.examples, name
    assert runner.failures == 0, "".join(out)


def test_the_reference_names_no_repository_file():
    """A user has the wheel: the reference's docstrings (and the public
    packages' own, which ``help()`` and the API pages show) name no folder of
    the repository, no source file and not the developers' notes."""
    docs = {n: _doc_of(o, c) for n, o, c in reference_callables()}
    docs.update({p: importlib.import_module(p).__doc__ or "" for p in REFERENCE + ("pdbfs.errors",)})
    bad = [f"{n}: {m.group(0)}" for n, d in docs.items() for m in REPOSITORY_PATH.finditer(d)
           if not m.group(0).endswith(".py") or m.group(0).rsplit("/", 1)[-1] in REPOSITORY_FILES]
    assert not bad, f"{len(bad)} repository paths:\n  " + "\n  ".join(bad)


def test_no_docstring_names_what_a_wheel_does_not_hold():
    """Internal modules may name their neighbours (a layout map), but no
    docstring anywhere names the repository's scripts, tests or notes."""
    bad = []
    for mod in modules():
        docs = {mod.__name__: mod.__doc__ or ""}
        for name, obj in vars(mod).items():
            if getattr(obj, "__module__", None) == mod.__name__ and \
                    (inspect.isclass(obj) or inspect.isfunction(obj)):
                docs[f"{mod.__name__}.{name}"] = obj.__doc__ or ""
                if inspect.isclass(obj):
                    docs.update({f"{mod.__name__}.{name}.{m}": f.__doc__ or ""
                                 for m, v in vars(obj).items() if (f := _function_of(v)) is not None})
        bad += [f"{n}: {m.group(0)}" for n, d in docs.items() for m in NOT_IN_WHEEL.finditer(d)]
    assert not bad, f"{len(bad)} names of what a wheel lacks:\n  " + "\n  ".join(bad)


def test_the_api_pages_render_sections_as_tables():
    """mkdocstrings reads NumPy sections and renders them as tables."""
    text = (API_PAGES.parents[2] / "mkdocs.yml").read_text()
    options = text[text.index("mkdocstrings:"):text.index("markdown_extensions:")]
    assert re.search(r"^ +docstring_style: numpy$", options, re.M)
    assert re.search(r"^ +docstring_section_style: table$", options, re.M)
