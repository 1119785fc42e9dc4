"""MkDocs hooks (mkdocs.yml ``hooks:``): the reference pages made from the
code itself, so nothing is written twice.

* ``reference/cli.md``: every command and option, from ``pdbfs.cli.build_parser``;
* ``reference/components.md``: the component catalogue, one section per
  domain (each subpackage of ``pdbfs.components``), from each component's
  own equations (as its docstring states them), ``Parameter``
  declarations, connectors and variables;
* ``reference/rigs.md``: the rigs ``--rig`` accepts, with their parameters.

The API pages (``::: pdbfs...``) are read by mkdocstrings from the sources.
pdbfs maps ``pdbfs.components``, ``pdbfs.models`` and ``pdbfs.fmu`` to
top-level folders (pyproject.toml's package-dir), which static analysis
cannot follow, so the hook lays out the package as Python sees it (symbolic
links in a temporary folder) and points mkdocstrings there.
"""
from __future__ import annotations

import argparse
import inspect
import re
import shutil
import tempfile
from pathlib import Path

from mkdocs.plugins import event_priority
from mkdocs.structure.files import File

ROOT = Path(__file__).resolve().parents[1]
_STAGE: list[Path] = []


@event_priority(100)          # before mkdocstrings makes its handler from the paths
def on_config(config):
    stage = Path(tempfile.mkdtemp(prefix="pdbfs-api-"))
    _STAGE.append(stage)
    pkg = stage / "pdbfs"
    pkg.mkdir()
    for entry in (ROOT / "pdbfs").iterdir():
        if entry.name != "__pycache__":
            (pkg / entry.name).symlink_to(entry)
    for name in ("components", "models", "fmu"):
        (pkg / name).symlink_to(ROOT / name)
    python = config.plugins["mkdocstrings"].config["handlers"].setdefault("python", {})
    python["paths"] = [str(stage)]
    return config


def on_shutdown():
    for stage in _STAGE:
        shutil.rmtree(stage, ignore_errors=True)


def on_files(files, config):
    pages = {"reference/cli.md": cli_page, "reference/components.md": components_page,
             "reference/rigs.md": rigs_page}
    for uri, make in pages.items():
        files.append(File.generated(config, uri, content=make()))
    return files


# --- the command line --------------------------------------------------------------------

def _cell(text) -> str:
    """Text for a Markdown table cell."""
    return " ".join(str(text).split()).replace("|", "\\|")


def _option_row(action) -> str:
    names = ", ".join(f"`{o}`" for o in action.option_strings) or f"`{action.dest}`"
    if action.nargs == 0:
        value = ""
    elif action.choices:
        value = " \\| ".join(f"`{c}`" for c in action.choices)
    else:
        value = f"`{action.metavar or action.dest.upper()}`"
    default = action.default
    shown = "" if default in (None, False, argparse.SUPPRESS) or action.nargs == 0 \
        else f"`{default}`"
    return f"| {names} | {value} | {shown} | {_cell(action.help or '')} |"


#: a fenced block of shell commands, and a comment that keeps a block from running
_SHELL = re.compile(r"^```(?:bash|console)\n(.*?)^```", re.S | re.M)
_SKIPPED = re.compile(r"<!--\s*docs-test:\s*skip:")


def command_examples() -> dict[str, tuple[str, str]]:
    """For each command, the first ``pdbfs COMMAND ...`` line the docs pages
    show (and the docs tests run: none in a skipped block, none the page shows
    refused), with the page it is on: command -> (line, page)."""
    docs = ROOT / "docs"
    found: dict[str, tuple[str, str]] = {}
    order = ("getting-started.md", "index.md", "tutorials/", "how-to/", "explanation/")
    pages = sorted(docs.rglob("*.md"), key=lambda p: (
        next((i for i, o in enumerate(order) if p.relative_to(docs).as_posix().startswith(o)),
             len(order)), p))
    for page in pages:
        rel = page.relative_to(docs).as_posix()
        if rel.startswith(("reference/", "figures/")):
            continue
        text = page.read_text()
        for m in _SHELL.finditer(text):
            if _SKIPPED.search(text[max(0, m.start() - 300):m.start()].rsplit("```", 1)[-1]):
                continue
            lines = m.group(1).replace("\\\n", " ").splitlines()
            for i, raw in enumerate(lines):
                line = raw[2:] if raw.startswith("$ ") else raw
                line = re.split(r"\s+#", line)[0].strip()
                refused = i + 1 < len(lines) and lines[i + 1].startswith("pdbfs: error:")
                words = line.split()
                if len(words) > 1 and words[0] == "pdbfs" and not refused:
                    found.setdefault(words[1], (" ".join(words), rel))
    return found


def cli_page() -> str:
    from pdbfs.cli import build_parser
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    helps = {a.dest: a.help for a in sub._choices_actions}
    examples = command_examples()
    out = ["# Command line", "",
           "Generated from the command line's own parser: what `pdbfs COMMAND --help` prints, "
           "as tables. Every command takes `--help`; `pdbfs --version` prints the version.", ""]
    out += [f"- [`pdbfs {name}`](#pdbfs-{name}): {_cell(helps.get(name, ''))}" for name in sub.choices]
    for name, p in sub.choices.items():
        out += ["", f"## `pdbfs {name}` {{#pdbfs-{name}}}", "", _cell(helps.get(name, "")) + ".", ""]
        if p.description:
            out += [p.description, ""]
        usage = p.format_usage().strip().removeprefix("usage: ")
        out += ["```text", usage, "```", ""]
        if name in examples:
            line, page = examples[name]
            out += [f"For example (from [{page.removesuffix('.md')}](../{page})):", "",
                    "```bash", line, "```", ""]
        out += ["| option | value | default | meaning |", "|---|---|---|---|"]
        out += [_option_row(a) for a in p._actions if not isinstance(a, argparse._HelpAction)]
        if p.epilog:
            out += ["", p.epilog]
    return "\n".join(out) + "\n"


# --- the component catalogue -------------------------------------------------------------

def _number(v) -> str:
    return f"{v:g}" if isinstance(v, (int, float)) and not isinstance(v, bool) else str(v)


def _limits(decl) -> str:
    parts = ["> 0"] if decl.positive else []
    if decl.min is not None:
        parts.append(f">= {_number(decl.min)}")
    if decl.max is not None:
        parts.append(f"<= {_number(decl.max)}")
    if not decl.tunable:
        parts.append("fixed")
    return ", ".join(parts)


def declared_parameters(cls) -> dict:
    """A component class's Parameter declarations, bases first (as Component does)."""
    from pdbfs import Parameter
    decls = {}
    for klass in reversed(cls.__mro__):
        for name, d in vars(klass).items():
            if isinstance(d, Parameter):
                decls[name] = d
    return decls


def _doc(obj) -> str:
    return inspect.cleandoc(obj.__doc__ or "").split("\n\n")[0].replace("\n", " ")


def _options(cls) -> list[str]:
    """Constructor arguments that are not parameters (structure: laws, flags, sizes)."""
    try:
        sig = inspect.signature(cls.__init__)
    except (TypeError, ValueError):
        return []
    return [f"`{p.name}={p.default!r}`" if p.default is not p.empty else f"`{p.name}`"
            for p in list(sig.parameters.values())[1:]
            if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)]


#: a ``code span`` of a docstring
CODE = re.compile(r"``(.+?)``")


def equations_of(cls) -> list[str]:
    """The equations a component's docstring states, in its order: its code
    spans with " = " in them (not a line of Python: ``self.x = ...``)."""
    spans = CODE.findall(" ".join((cls.__doc__ or "").split()))
    return list(dict.fromkeys(c for c in spans if " = " in c and not c.startswith("self.")))


def component_section(cls, module: str, anchor: str) -> list[str]:
    out = ["", f"### {cls.__name__} {{#{anchor}}}", "", f"`{module}.{cls.__name__}`: {_doc(cls)}", ""]
    eqs = equations_of(cls)
    if eqs:
        out += ["Equations: " + "; ".join(f"`{_cell(e)}`" for e in eqs) + ".", ""]
    options = _options(cls)
    if options:
        out += ["Options (structure, fixed when the rig is built): " + ", ".join(options) + ".", ""]
    decls = declared_parameters(cls)
    if decls:
        out += ["| parameter | unit | default | limits | description |", "|---|---|---|---|---|"]
        out += [f"| `{n}` | {_cell(d.unit)} | {_cell(_number(d.default))} | {_limits(d)} | "
                f"{_cell(d.description)} |" for n, d in decls.items()]
        out.append("")
    try:
        inst = cls()
    except Exception:  # noqa: BLE001 - a component that needs a size: connectors depend on it
        return out
    conns = [f"`{n}` ({type(c).__name__})" for n, c in inst._connectors.items()]
    if conns:
        out += ["Connectors: " + ", ".join(conns) + ".", ""]
    if inst._vars:
        out += ["| variable | unit | description |", "|---|---|---|"]
        out += [f"| `{n}` | {_cell(v.decl.unit)} | {_cell(v.decl.description)} |"
                for n, v in inst._vars.items()]
        out.append("")
    return out


def domains() -> list[tuple[str, object]]:
    """(title, module) of each domain of the component library: every
    subpackage of ``pdbfs.components`` (a new domain appears by itself),
    translational mechanics first, the signal blocks last. The title is the
    first words of the subpackage's docstring."""
    import importlib
    import pkgutil

    import pdbfs.components as library
    names = [m.name for m in pkgutil.iter_modules(library.__path__) if m.ispkg]
    names.sort(key=lambda n: (n == "blocks", n != "translational", n))
    out = []
    for name in names:
        mod = importlib.import_module(f"{library.__name__}.{name}")
        first = inspect.cleandoc(mod.__doc__ or name).split("\n\n")[0].replace("\n", " ")
        title = re.split(r"[:,.(]", first, maxsplit=1)[0].strip()
        out.append((title, mod))
    return out


def domain_classes(mod) -> list[type]:
    """The component classes a domain exports (``__all__``), by name."""
    from pdbfs import Component
    classes = [getattr(mod, n) for n in getattr(mod, "__all__", [])]
    return sorted((c for c in classes if inspect.isclass(c) and issubclass(c, Component)),
                  key=lambda c: c.__name__)


def is_partial(cls) -> bool:
    """A base to build components on: a Partial... class, or one of a domain's
    ``interfaces`` module (the blocks' Block, SO, SISO, MISO)."""
    return cls.__name__.startswith("Partial") or cls.__module__.endswith(".interfaces")


def public_module(cls, mod) -> str:
    """The shortest import path of ``cls``: ``pdbfs.components`` for what it
    re-exports (the translational components), else its domain's package."""
    import pdbfs.components as library
    return library.__name__ if getattr(library, cls.__name__, None) is cls else mod.__name__


def components_page() -> str:
    out = ["# Component catalogue", "",
           "Generated from each component's own declarations: its equations (from its "
           "description), its parameters (name, SI unit, default, limits, description), the "
           "options its constructor takes, its connectors and its variables. `fixed` marks a "
           "parameter that cannot change during a run (a start value, a mass, an exponent); the "
           "rest are tunable. Partial components are bases to build new ones on (see the "
           "tutorial on building a rig).", ""]
    sections = domains()
    out += [f"- [{title}](#{domain_anchor(mod)}): " + ", ".join(
        f"`{c.__name__}`" for c in domain_classes(mod) if not is_partial(c)) for title, mod in sections]
    anchors = component_anchors()
    for title, mod in sections:
        classes = domain_classes(mod)
        top = {public_module(c, mod) for c in classes} - {mod.__name__}
        also = f" (also `{top.pop()}`)" if top else ""
        out += ["", f"## {title} {{#{domain_anchor(mod)}}}", "", f"`{mod.__name__}`{also}"]
        for cls in (c for c in classes if not is_partial(c)):
            out += component_section(cls, public_module(cls, mod), anchors[cls])
        partial = [c for c in classes if is_partial(c)]
        if partial:
            out += ["", f"### Partial bases ({title.lower()})", ""]
            out += [f"- `{cls.__name__}`: {_doc(cls)}" for cls in partial]
        out.append("")
    return "\n".join(out) + "\n"


def domain_anchor(mod) -> str:
    """A domain's anchor on the catalogue page: its subpackage's name."""
    return mod.__name__.rsplit(".", 1)[1]


def component_anchors() -> dict[type, str]:
    """Each catalogued component's anchor: its name in lower case, or, for a
    name another domain has used already, the domain's anchor before it
    (``hydraulic-pressuresensor``)."""
    out, used = {}, set()
    for _, mod in domains():
        for cls in domain_classes(mod):
            if not is_partial(cls):
                name = cls.__name__.lower()
                out[cls] = name if name not in used else f"{domain_anchor(mod)}-{name}"
                used.add(name)
    return out


# --- the rigs ----------------------------------------------------------------------------

def rigs_page() -> str:
    from pdbfs.models import RIGS, rig_description
    out = ["# Rigs", "",
           "The rigs `--rig NAME` accepts (`pdbfs.models.RIGS`), each built from the component "
           "library, with its inputs and every parameter as the rig declares it (`pdbfs rigs` "
           "and `pdbfs params --rig NAME` print the same). `--rig` also takes a rig of your "
           "own: `FILE.py:NAME` or `MODULE:NAME`.", ""]
    for name, build in RIGS.items():
        rig = build()
        params = rig.parameters()
        doc = _cell(rig_description(name, rig))
        out += [f"## `{name}`", "", f"{doc[:1].upper()}{doc[1:]} (class `{type(rig).__name__}`, "
                f"{len(params)} parameters).", ""]
        inputs = rig.inputs()
        if inputs:
            out += ["Inputs: " + "; ".join(f"`{u.name}` ({_cell(u.unit)}): {_cell(u.description)}"
                                           for u in inputs) + ".", ""]
        out += [f'??? note "Parameters of {name}"', "",
                "    | parameter | unit | default | description |", "    |---|---|---|---|"]
        out += [f"    | `{p.name}` | {_cell(p.unit)} | "
                f"{_cell(_number(p.value) if isinstance(p.value, (int, float)) else 'computed')} | "
                f"{_cell(p.description)} |" for p in params]
        out.append("")
    return "\n".join(out) + "\n"
