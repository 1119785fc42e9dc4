"""The documentation builds, its examples run, and it points only at what a
user has.

- `mkdocs build --strict` (warnings as errors: a broken link or anchor, a
  page missing from the navigation, a docstring mkdocstrings cannot read)
  into a temporary folder; the generated references list every command,
  component and rig;
- every ```python block of README, CONTRIBUTING and the docs pages runs
  (each page's blocks in order, in one namespace, in a temporary folder);
- every `pdbfs ...` command in their bash and console blocks runs with exit
  status 0, or 2 where the page shows it refused (a few at a smaller size,
  docs_examples.OVERRIDES, each with its reason);
- no page names a file a user does not have, and no page tells history.
"""
import argparse
import inspect
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

import docs_examples as D

ROOT = D.ROOT
PAGES = D.pages()


def test_every_page_is_tested():
    """The page list the tests walk holds README and every docs page."""
    ids = {D.page_id(p) for p in PAGES}
    assert {"README.md", "CONTRIBUTING.md", "docs/index.md", "docs/tutorials/own-rig.md"} <= ids
    assert len(ids) >= 20


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    pytest.importorskip("mkdocs", reason="mkdocs is not installed (pip install 'pdbfs[docs]')")
    pytest.importorskip("mkdocstrings_handlers.python", reason="mkdocstrings-python is not installed")
    out = tmp_path_factory.mktemp("site")
    r = D.build_site(out)
    assert r.returncode == 0, r.stderr[-4000:]
    return out


def test_the_docs_build_strictly(site):
    assert (site / "index.html").is_file()
    for page in ("getting-started", "tutorials/own-rig", "reference/api/pdbfs", "benchmarks"):
        assert (site / page / "index.html").is_file(), page


def test_the_command_line_reference_has_every_command_and_option(site):
    from pdbfs.cli import build_parser
    html = (site / "reference" / "cli" / "index.html").read_text()
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, parser in sub.choices.items():
        assert f'id="pdbfs-{name}"' in html, name
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):       # every command has --help
                continue
            for opt in action.option_strings:
                assert f"<code>{opt}</code>" in html, (name, opt)


def _hooks():
    """The docs build's hooks module (scripts/mkdocs_hooks.py), as the build loads it."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("mkdocs_hooks", ROOT / "scripts" / "mkdocs_hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_component_catalogue_has_every_domain_component_and_parameter(site):
    """One section per subpackage of pdbfs.components (translational,
    hydraulic, the blocks, and any domain added later), and in it every
    component with its equations and every parameter."""
    import pkgutil

    import pdbfs.components as library
    from pdbfs import Parameter
    H = _hooks()
    html = (site / "reference" / "components" / "index.html").read_text()
    found = {mod.__name__.rsplit(".", 1)[1] for _, mod in H.domains()}
    assert found == {m.name for m in pkgutil.iter_modules(library.__path__) if m.ispkg}
    assert {"translational", "hydraulic", "blocks"} <= found
    anchors = H.component_anchors()
    assert {"Limiter", "PID", "Table", "Gain", "Input"} <= {c.__name__ for c in anchors}
    for _, mod in H.domains():
        assert f'id="{H.domain_anchor(mod)}"' in html, mod.__name__
    for cls, anchor in anchors.items():
        section = html.split(f'id="{anchor}"', 1)
        assert len(section) == 2, anchor
        own = section[1].split("<h3", 1)[0]
        assert "Equations:" in own, f"{cls.__name__}: its docstring states no equation"
        params = {n for k in cls.__mro__ for n, d in vars(k).items() if isinstance(d, Parameter)}
        for p in params:
            assert f"<code>{p}</code>" in own, (cls.__name__, p)


def test_the_search_finds_every_block_and_every_study_by_name(site):
    """The site's search index has a heading of each name: every component
    (blocks included) in the catalogue, every study in the API reference."""
    import pdbfs.studies
    index = json.loads((site / "search" / "search_index.json").read_text())["docs"]
    titles = {d["title"].split()[0] for d in index if d["title"].strip()}   # "Name  <code>dataclass</code>"
    H = _hooks()
    for cls in H.component_anchors():
        assert cls.__name__ in titles, cls.__name__
    for name in pdbfs.studies.__all__:
        obj = getattr(pdbfs.studies, name)
        if inspect.isclass(obj) or inspect.isfunction(obj):
            assert name in titles, name


#: what a built page may load from elsewhere: nothing (an offline machine loads the site
#: whole); links a reader follows are fine
LOADS = re.compile(r"""<(?:link|script|img|iframe|source)\b[^>]*?\b(?:href|src)=["']?(?:https?:)?//""", re.I)
CSS_LOADS = re.compile(r"""@import\s+(?:url\()?["']?(?:https?:)?//|url\(["']?(?:https?:)?//""", re.I)


def test_the_built_site_loads_nothing_from_another_host(site):
    """No web font, script, stylesheet or image from another host: the site
    works the same offline (no font host waited for)."""
    pages = list(site.rglob("*.html"))
    assert len(pages) > 20
    for page in pages:
        m = LOADS.search(page.read_text())
        assert not m, f"{page.relative_to(site)} loads {m.group(0)}"
    for css in site.rglob("*.css"):
        m = CSS_LOADS.search(css.read_text())
        assert not m, f"{css.relative_to(site)}: {m.group(0)}"
    assert "fonts.googleapis" not in (site / "index.html").read_text()


def test_every_command_in_the_reference_has_an_example_the_docs_tests_run(site):
    """Each command's section shows one command line from a docs page (the
    first there), a line the shell-example test runs on that page."""
    from pdbfs.cli import build_parser
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    examples = _hooks().command_examples()
    html = (site / "reference" / "cli" / "index.html").read_text()
    for name in sub.choices:
        assert name in examples, f"no docs page shows `pdbfs {name}`"
        line, page = examples[name]
        run = [c.line for c in D.commands((D.DOCS / page).read_text()) if not c.skip and not c.refused]
        assert line in run, (name, page, line)
        section = html.split(f'id="pdbfs-{name}"', 1)[1].split("<h2", 1)[0]
        assert "For example" in section and line.split()[1] in section, name


def test_the_rigs_page_has_every_rig(site):
    from pdbfs.models import RIGS
    html = (site / "reference" / "rigs" / "index.html").read_text()
    for name in RIGS:
        assert f"<code>{name}</code>" in html, name


# --- Python examples ---------------------------------------------------------------------

PY_PAGES = [p for p in PAGES if D.python_blocks(p.read_text())]


@pytest.mark.parametrize("page", PY_PAGES, ids=D.page_id)
def test_python_examples_run(page, tmp_path, monkeypatch):
    text = page.read_text()
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    ran = 0
    for block in D.python_blocks(text):
        if block.skip:
            continue
        code = compile(block.body, f"{D.page_id(page)}:{block.line}", "exec")
        exec(code, namespace)
        ran += 1
    if not ran:
        pytest.skip("every Python block of this page is marked not to run")


# --- shell examples ----------------------------------------------------------------------

SH_PAGES = [p for p in PAGES if D.commands(p.read_text())]


@pytest.mark.parametrize("page", SH_PAGES, ids=D.page_id)
def test_shell_examples_run(page, tmp_path):
    text = page.read_text()
    ran = 0
    for cmd in D.commands(text):
        if cmd.skip:
            continue
        args, _ = D.as_run(cmd.line)
        if args[0] in D.PARSE_ONLY:
            assert D.pdbfs([args[0], "--help"], tmp_path).returncode == 0
            ran += 1
            continue
        r = D.pdbfs(args, tmp_path)
        where = f"{D.page_id(page)}: {cmd.line}"
        if cmd.line in D.KNOWN_FAILURES:
            assert r.returncode != 0, f"{where} runs now: remove it from KNOWN_FAILURES"
            continue
        assert "Traceback" not in r.stderr, f"{where}\n{r.stderr[-3000:]}"
        if cmd.refused:         # the page shows it refused: one line, exit status 2
            assert r.returncode == 2 and r.stderr.strip().count("\n") == 0, f"{where}\n{r.stderr}"
            assert r.stderr.startswith("pdbfs: error:"), where
            continue
        assert r.returncode == 0, f"{where}\n{r.stderr[-3000:]}"
        if "--json" in args:
            json.loads(r.stdout)
        ran += 1
    assert ran >= 1 or all(c.skip or c.refused for c in D.commands(text))


# --- what pages point at -----------------------------------------------------------------

#: what no page names: the developers' own folders and files, absolute paths of a machine
FORBIDDEN = [r"\.\./shared", r"/work/", r"PHYSICS\.md", r"NOTES\.md", r"/home/\w", r"/root/",
             r"\bC:\\\\Users"]
#: history is CHANGELOG.md's
HISTORY = [r"\bthis release\b", r"\bthe release before\b", r"\bnext release\b",
           r"\bissue #?\d+", r"\bfor the next attempt\b", r"(?<![\w/])#\d{1,3}\b"]


@pytest.mark.parametrize("page", PAGES, ids=D.page_id)
def test_no_page_names_a_file_the_user_does_not_have(page):
    text = page.read_text()
    for pattern in FORBIDDEN:
        assert not re.search(pattern, text), f"{D.page_id(page)} names {pattern}"
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+://|mailto:|#", target):
            continue
        path = (page.parent / target.split("#")[0]).resolve()
        if D.DOCS in page.parents and path.relative_to(D.DOCS.resolve()).as_posix() in D.GENERATED:
            continue                # made by the docs build (mkdocs checks these links)
        assert path.exists(), f"{D.page_id(page)} links to {target}, which does not exist"
        assert ROOT in path.parents or path == ROOT, f"{D.page_id(page)} links outside: {target}"


#: the repository's own folders, and Python or shell files other than the example scripts
#: the pages include (a user downloads those from the page)
REPOSITORY = re.compile(r"\b(?:scripts|tests)/|\b[\w/.-]+\.(?:py|sh)\b")
DOCS_PAGES = [p for p in PAGES if D.DOCS in p.parents]
#: the names of the repository's Python and shell files (a page may name a file of the user's own)
REPOSITORY_FILES = {p.name for top in ROOT.iterdir() if top.is_dir() and not top.name.startswith(".")
                    for p in top.rglob("*") if p.suffix in (".py", ".sh")}


@pytest.mark.parametrize("page", DOCS_PAGES, ids=D.page_id)
def test_no_docs_page_names_a_repository_file(page):
    """A docs page is for someone with the wheel alone: it names no folder or
    source file of the repository (its comments included), only the example
    scripts it includes."""
    examples = {p.name for p in D.EXAMPLES.glob("*.py")}
    for m in REPOSITORY.finditer(page.read_text()):
        name = m.group(0).rsplit("/", 1)[-1]
        if m.group(0).endswith("/") or name in REPOSITORY_FILES:     # a user's own file may be named
            assert name in examples, f"{D.page_id(page)} names {m.group(0)}"


EXAMPLE_FILES = sorted(D.EXAMPLES.glob("*.py"))


@pytest.mark.parametrize("script", EXAMPLE_FILES, ids=lambda p: p.name)
def test_the_example_scripts_are_shown_and_run(script, tmp_path):
    """Each example script is included whole by a page that links it for
    download, and runs as a user runs it (`python NAME --out figures`),
    writing its figures and numbers there (some smaller: EXAMPLE_ARGS says
    why)."""
    include = f'--8<-- "examples/{script.name}"'
    showing = [p for p in DOCS_PAGES if include in p.read_text()]
    assert showing, f"no page includes {script.name}"
    assert all(f"(../examples/{script.name})" in p.read_text() for p in showing)
    args, _why = D.EXAMPLE_ARGS[script.name]
    r = subprocess.run([sys.executable, str(script), "--out", "figures", *args], cwd=tmp_path,
                       capture_output=True, text=True, timeout=900)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr[-3000:]
    made = {p.suffix for p in (tmp_path / "figures").iterdir()}
    assert {".png", ".json"} <= made, made
    assert [p.name for p in tmp_path.iterdir()] == ["figures"]     # only where --out says


def test_every_example_script_has_its_test_arguments():
    assert set(D.EXAMPLE_ARGS) == {p.name for p in EXAMPLE_FILES}


@pytest.mark.parametrize("page", PAGES, ids=D.page_id)
def test_no_page_tells_history(page):
    text = page.read_text()
    for pattern in HISTORY:
        m = re.search(pattern, text, flags=re.I)
        assert not m, f"{D.page_id(page)}: {m.group(0)!r} (history belongs in CHANGELOG.md)"


def test_the_docs_data_is_not_named_by_examples():
    """The examples use the data the package ships (pdbfs example-data), not
    the repository's docs/data, which an installed package does not have."""
    for page in PAGES:
        for block in D.blocks(page.read_text()):
            assert "docs/data" not in block.body, f"{D.page_id(page)}:{block.line}"


def test_license_is_bsd_3_clause():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("BSD 3-Clause License")
    assert "Copyright (c) 2026, The pdbfs developers" in text
    assert "Neither the name of the copyright holder" in text
