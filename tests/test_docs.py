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
    r = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f",
                        str(ROOT / "mkdocs.yml"), "-d", str(out)], capture_output=True, text=True,
                       cwd=ROOT, timeout=600, env={**__import__("os").environ, "NO_MKDOCS_2_WARNING": "1"})
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


def test_the_component_catalogue_has_every_component_and_parameter(site):
    import pdbfs.components as mech
    import pdbfs.components.hydraulic as hyd
    from pdbfs import Component, Parameter
    html = (site / "reference" / "components" / "index.html").read_text()
    for mod in (mech, hyd):
        for name in mod.__all__:
            cls = getattr(mod, name)
            if not (inspect.isclass(cls) and issubclass(cls, Component)) or name.startswith("Partial"):
                continue
            section = html.split(f'id="{name.lower()}"', 1)
            assert len(section) == 2, name
            params = {n for k in cls.__mro__ for n, d in vars(k).items() if isinstance(d, Parameter)}
            for p in params:
                assert f"<code>{p}</code>" in section[1][:20000], (name, p)


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
