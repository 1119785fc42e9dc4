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
          "models": "models", "fmu": "fmu"}
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
    "studies": {"errors", "files", "modelling", "simulation", "components", "models", "rig"},
    "cli": {"errors", "files", "modelling", "simulation", "fmu", "studies", "models", "components", "rig",
            "app"},
    "app": {"errors", "files", "modelling", "simulation", "studies", "models", "components", "rig"},
}
#: pdbfs.<name> -> stage
TARGETS = {"modelling": "modelling", "native": "native", "simulation": "simulation",
           "studies": "studies", "cli": "cli", "app": "app", "components": "components",
           "models": "models", "fmu": "fmu", "errors": "errors", "files": "files", "rig": "rig"}
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


def imported(path: pathlib.Path):
    """(line, dotted name) of every pdbfs import in the file, relative ones resolved."""
    tree = ast.parse(path.read_text())
    pkg = package_of(path)
    for node in ast.walk(tree):
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
    batch = (ROOT / "pdbfs/simulation/c/pdbfs_batch.c").read_text()
    cosim = (ROOT / "fmu/c/cosimulation.c").read_text()
    for text in (batch, cosim):
        assert "pdbfs_cvode_advance(" in text and "CVode(" not in text
