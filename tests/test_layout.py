"""The layout shows the architecture: every stage is a package that says what
it holds and what it may import; imports only go down the chain
(studies -> simulation -> modelling compiler; the FMU and the compiled
backend share pdbfs.native); no file is long."""
import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
#: package directory -> stage; pdbfs.components, .models and .fmu live at the top
STAGES = {"pdbfs/modelling": "modelling", "pdbfs/native": "native", "pdbfs/simulation": "simulation",
          "pdbfs/studies": "studies", "pdbfs/cli": "cli", "pdbfs/app": "app", "components": "components",
          "models": "models", "fmu": "fmu", "pdbfs/fatigue": "fatigue"}
MODULES = {"pdbfs/errors.py": "errors", "pdbfs/files.py": "files", "pdbfs/rig.py": "rig", "pdbfs/__init__.py": "api"}
#: what each stage may import (besides itself)
ALLOWED = {
    "errors": set(),
    "files": {"errors"},
    "modelling": {"errors", "files"},
    "components": {"errors", "files", "modelling"},
    "native": {"errors", "files", "modelling"},
    "simulation": {"errors", "files", "modelling", "native"},
    "fmu": {"errors", "files", "modelling", "native"},
    "rig": {"errors", "files", "modelling", "simulation", "fmu"},
    "models": {"errors", "files", "modelling", "components", "rig"},
    "fatigue": {"errors", "files"},
    "studies": {"errors", "files", "modelling", "simulation", "components", "models", "rig",
                "fatigue"},
    "cli": {"errors", "files", "modelling", "simulation", "fmu", "studies", "models", "components", "rig",
            "app", "fatigue"},
    "app": {"errors", "files", "modelling", "simulation", "studies", "models", "components", "rig",
            "fatigue"},
}
#: pdbfs.<name> -> stage
TARGETS = {"modelling": "modelling", "native": "native", "simulation": "simulation",
           "studies": "studies", "cli": "cli", "app": "app", "components": "components",
           "models": "models", "fmu": "fmu", "errors": "errors", "files": "files", "rig": "rig",
           "fatigue": "fatigue"}
MAX_LINES = 400


def stage_of(path: pathlib.Path):
    rel = path.relative_to(ROOT).as_posix()
    if rel in MODULES:
        return MODULES[rel]
    for d, stage in STAGES.items():
        if rel.startswith(d + "/"):
            return stage
    return None


def package_of(path: pathlib.Path) -> list[str]:
    """The dotted package of a module file, as Python sees it (pdbfs.*)."""
    rel = path.relative_to(ROOT).parent.as_posix()
    top = {"components": "pdbfs.components", "models": "pdbfs.models", "fmu": "pdbfs.fmu"}
    head, _, tail = rel.partition("/")
    base = top.get(head, head)
    return (base + ("." + tail.replace("/", ".") if tail else "")).split(".")


def _typing_only(tree) -> set:
    """The import nodes under ``if TYPE_CHECKING:``: they name types for
    annotations and never run, so they are no dependency (not counted)."""
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip |= {id(n) for b in node.body for n in ast.walk(b)}
    return skip


def imported(path: pathlib.Path):
    """(line, dotted name) of every pdbfs import in the file, relative ones
    resolved, but those for annotations only (``if TYPE_CHECKING:``)."""
    tree = ast.parse(path.read_text())
    pkg = package_of(path)
    typing_only = _typing_only(tree)
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            for a in node.names:
                yield node.lineno, a.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg[: len(pkg) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
                names = [mod] if node.module else [f"{mod}.{a.name}" for a in node.names]
            else:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            for n in names:
                yield node.lineno, n


def target_stage(name: str):
    parts = name.split(".")
    if parts[0] != "pdbfs" or len(parts) < 2:
        return None
    stage = TARGETS.get(parts[1])
    if stage == "components" and len(parts) > 2 and parts[2] == "laws":
        return "components.laws"
    return stage


SOURCES = sorted(p for d in ("pdbfs", "components", "models", "fmu") for p in (ROOT / d).rglob("*.py"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_imports_only_go_down(path):
    stage = stage_of(path)
    assert stage is not None, f"{path} belongs to no stage"
    if stage == "api":
        return
    bad = []
    for line, name in imported(path):
        t = target_stage(name)
        if t is None or t == stage or (t == "components.laws" and stage == "components"):
            continue
        allowed = ALLOWED[stage]
        if t not in allowed and not (t == "components.laws" and "components" in allowed):
            bad.append(f"line {line}: {name} ({t})")
    assert not bad, f"{stage} may import {sorted(ALLOWED[stage])}, but imports " + "; ".join(bad)


@pytest.mark.parametrize("pkg", sorted(STAGES) + ["pdbfs/studies/paper"])
def test_every_stage_says_what_it_holds_and_may_import(pkg):
    init = ROOT / pkg / "__init__.py"
    doc = ast.get_docstring(ast.parse(init.read_text()))
    assert doc and len(doc.splitlines()) >= 3, f"{init} needs a docstring"
    if pkg != "pdbfs/studies/paper":
        assert "May import" in doc, f"{init}: say what the stage may import"


def test_no_file_is_long():
    files = [p for d in ("pdbfs", "components", "models", "fmu", "scripts") for p in (ROOT / d).rglob("*")
             if p.suffix in (".py", ".c", ".h", ".sh")]
    long = {p.relative_to(ROOT).as_posix(): n for p in files
            if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert not long, f"files over {MAX_LINES} lines: {long}"


def test_the_c_drivers_share_one_cvode_loop():
    """The compiled backend and the FMU integrate with the same CVODE driver,
    and neither has a copy of it."""
    batch = (ROOT / "pdbfs/native/c/library/pdbfs_batch.c").read_text()
    cosim = (ROOT / "pdbfs/native/c/fmu/cosimulation.c").read_text()
    for text in (batch, cosim):
        assert "pdbfs_cvode_advance(" in text and "CVode(" not in text


def dotted(path: pathlib.Path) -> str:
    """A module file's name as Python imports it (pdbfs.*)."""
    pkg = package_of(path)
    return ".".join(pkg if path.name == "__init__.py" else pkg + [path.stem])


MODULE_FILES = {dotted(p): p for p in SOURCES}


def module_targets(path: pathlib.Path, annotations: bool = False, source: str | None = None):
    """The project's modules that importing ``path`` runs, function-level
    imports included: the module named, or the modules named in a
    ``from ... import``, and the package imported from unless it is one of
    the module's own (already running when the module is); with
    ``annotations``, those named for annotations only (``if TYPE_CHECKING:``)
    too: a reader needs them to read the module (``source``: the text read
    in place of the file's)."""
    me, pkg = dotted(path), package_of(path)
    tree = ast.parse(path.read_text() if source is None else source)
    typing_only = set() if annotations else _typing_only(tree)
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(pkg[: len(pkg) - node.level + 1] + ([node.module] if node.module else [])) \
                if node.level else node.module
            subs = [f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in MODULE_FILES]
            yield from subs
            if len(subs) < len(node.names) or not (me + ".").startswith(base + "."):
                yield base


def import_graph() -> dict:
    """module -> the project's modules it imports (module_targets)."""
    return {m: {t for t in module_targets(p) if t in MODULE_FILES and t != m}
            for m, p in MODULE_FILES.items()}


def cycles(graph: dict) -> list:
    """The import circles of ``graph``: its strongly connected components of
    more than one module (Tarjan), each sorted."""
    index, low, stack, on, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1:
                found.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_module_imports_itself_through_others():
    """No import circle between the project's modules, function-level imports
    counted: a circle means neither module can be read (or moved) without the other."""
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]   # the finder
    assert "pdbfs.native.straight" in import_graph()["pdbfs.native.codegen"]
    found = cycles(import_graph())
    assert not found, "import circles: " + "; ".join(" <-> ".join(c) for c in found)


#: pdbfs.simulation's folders, in their order: each may import the folders
#: before it (and state.py, the layer's state per rig), never those after it
SIM = ROOT / "pdbfs/simulation"
SIM_FOLDERS = ("setup", "results", "run", "analysis")


def simulation_part(name: str):
    """The folder (or root module) of pdbfs.simulation that module ``name``
    belongs to; "" for the package itself, None outside it."""
    parts = name.split(".")
    if parts[:2] != ["pdbfs", "simulation"]:
        return None
    return parts[2] if len(parts) > 2 else ""


@pytest.mark.parametrize("path", sorted(p for p in SIM.rglob("*.py") if p != SIM / "__init__.py"),
                         ids=lambda p: p.relative_to(SIM).as_posix())
def test_the_simulation_folders_import_one_way(path):
    """setup <- results <- run <- analysis: a result never imports the run that
    makes it, a run never an analysis of runs, not even for annotations (a
    Result names what it reads of its run by a protocol of its own folder)."""
    part, bad = folder_breaches(path)
    assert not bad, f"pdbfs.simulation.{part} may import {sorted(allowed_parts(part))}, " \
        f"but imports {bad}"


def allowed_parts(part: str) -> set:
    """The parts of pdbfs.simulation that its part ``part`` may import."""
    if part == "state":
        return {part}
    return set(SIM_FOLDERS[:SIM_FOLDERS.index(part)]) | {part, "state"}


def folder_breaches(path: pathlib.Path, source: str | None = None) -> tuple[str, list]:
    """(the part of pdbfs.simulation ``path`` is in, the modules it imports
    against the folders' order, annotations' imports included)."""
    part = simulation_part(dotted(path))
    allowed = allowed_parts(part)
    return part, [t for t in module_targets(path, annotations=True, source=source)
                  if simulation_part(t) is not None and simulation_part(t) not in allowed]


def test_a_result_naming_its_simulator_for_annotations_breaks_the_order():
    """The check reads ``if TYPE_CHECKING:`` imports too: a results module
    that names the run's Simulator for its annotations (as Result once did)
    is refused, and one that names its own folder's protocol is not."""
    head = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from {} import {}\n"
    path = SIM / "results" / "result.py"
    assert folder_breaches(path, head.format("..run.simulator", "Simulator"))[1] == \
        ["pdbfs.simulation.run.simulator"]
    assert folder_breaches(path, head.format(".source", "RunSource"))[1] == []


def test_every_simulation_module_is_in_a_folder_that_lists_it():
    """A reader finds a run, a result and an analysis by the folder names:
    no module lies loose at the root but state.py, and each folder's
    docstring names each of its modules and what the folder may import."""
    loose = sorted(p.name for p in SIM.glob("*.py"))
    assert loose == ["__init__.py", "state.py"], loose
    assert sorted(p.name for p in SIM.iterdir() if p.is_dir() and p.name != "__pycache__") == \
        sorted(SIM_FOLDERS)
    for folder in SIM_FOLDERS:
        doc = ast.get_docstring(ast.parse((SIM / folder / "__init__.py").read_text()))
        assert doc and "May import" in doc, f"{folder}/__init__.py: say what it holds and may import"
        missing = [p.name for p in (SIM / folder).glob("*.py")
                   if p.name != "__init__.py" and p.name not in doc]
        assert not missing, f"{folder}/__init__.py does not list {missing}"


#: the dict methods that write
DICT_WRITES = {"setdefault", "update", "pop", "popitem", "clear", "__setitem__", "__delitem__"}


def writes_into_others(source: str) -> list:
    """Lines that write into another object's ``__dict__`` (or ``vars()``):
    any object but the method's own ``self`` (or ``cls``). What a layer
    keeps of another layer's object it keeps itself (e.g. pdbfs.simulation's
    RigState, held by the DAE as its companion)."""
    def others_dict(node) -> bool:
        if isinstance(node, ast.Attribute) and node.attr == "__dict__":
            owner = node.value
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and \
                node.func.id == "vars" and len(node.args) == 1:
            owner = node.args[0]
        else:
            return False
        return not (isinstance(owner, ast.Name) and owner.id in ("self", "cls"))

    bad = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Delete)):
            targets = node.targets if isinstance(node, (ast.Assign, ast.Delete)) else [node.target]
            if any(isinstance(s, ast.Subscript) and others_dict(s.value)
                   for t in targets for s in ast.walk(t)):
                bad.append(node.lineno)
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                node.func.attr in DICT_WRITES and others_dict(node.func.value):
            bad.append(node.lineno)
    return sorted(set(bad))


def test_the_checker_finds_writes_into_others():
    src = ("dae.__dict__['_x'] = 1\nsim.dae.__dict__.setdefault('_p', {})\nvars(r).update(s)\n"
           "del d.__dict__['a']\nx.__dict__['a']['b'] = 2\n"
           "self.__dict__['_f'] = 1\nself.__dict__.setdefault('_f', {})['g'] = 2\n"
           "n = dae.__dict__.get('_x')\nk = {a: b for a, b in vars(r).items()}\n")
    assert writes_into_others(src) == [1, 2, 3, 4, 5]


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_no_module_writes_into_another_objects_dict(path):
    """Each layer owns its own state: no module stashes its caches in another
    layer's objects through their __dict__ (the DAE offers ``companion`` and
    ``cached``, and a Result ``detached`` and ``attach``)."""
    bad = writes_into_others(path.read_text())
    assert not bad, f"writes into another object's __dict__ at lines {bad}"


def test_every_package_folder_is_in_the_wheel():
    """pyproject lists the packages by hand (three live outside pdbfs/): a
    folder left off installs as a wheel whose imports fail."""
    import tomllib
    conf = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    dirs = conf["package-dir"]
    listed = set(conf["packages"])
    found = set()
    for top, name in [("pdbfs", "pdbfs")] + [(d, n) for n, d in dirs.items() if n != "pdbfs"]:
        for init in (ROOT / top).rglob("__init__.py"):
            rel = init.parent.relative_to(ROOT / top).parts
            found.add(".".join((name, *rel)))
    assert found - listed == set(), f"package folders missing from pyproject's packages: {sorted(found - listed)}"
    assert listed - found == set(), f"pyproject lists packages with no folder: {sorted(listed - found)}"
