"""The examples of README.md, CONTRIBUTING.md and the docs pages, as the
tests run them (tests/test_docs.py, test_readme.py, test_readme_commands.py).

A fenced block is one example. ```python blocks run, each page's in order,
in one namespace, in a temporary folder. ```bash and ```console blocks hold
commands: every command that starts with ``pdbfs `` runs (continuation
lines joined, comments and ``$`` prompts removed); in a console block, the
lines after a command are its output, and an output line starting with
``pdbfs: error:`` means the page shows the command refused (exit status 2,
one line on stderr). A block preceded by ``<!-- docs-test: skip: REASON -->``
does not run.
"""
from __future__ import annotations

import re
import shlex
import subprocess
import sys
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: pages outside docs/ that users read
TOP_PAGES = ("README.md", "CONTRIBUTING.md")
#: pages the docs build makes from the code (scripts/mkdocs_hooks.py), relative to docs/
GENERATED = {"reference/cli.md", "reference/components.md", "reference/rigs.md"}
SKIP = re.compile(r"<!--\s*docs-test:\s*skip:\s*(.*?)\s*-->", re.S)

#: commands a page shows at a size that takes minutes: run here smaller, through the
#: same code (shown -> run, and why)
OVERRIDES = {
    "lhs:100000": ("lhs:64", "100,000 points take about a minute on two cores"),
    "lhs:2000": ("lhs:64", "the same code path as 2,000 points"),
    "mc:10000": ("mc:64", "the same code path as 10,000 draws"),
    "--n 4096": ("--n 8", "N (D + 2) = 20,480 simulations, several minutes"),
    "design-map --rig paper --x hammer.h=0.1:1.5 --y oil.k=1e8:1e9 --out map":
        ("design-map --rig paper --x hammer.h=0.1:1.5 --y oil.k=1e8:1e9 --out map --n 5",
         "the default 21 x 21 map is 441 simulations"),
    "reproduce --out figures": ("reproduce --out figures --figures fig5",
                                "every figure takes about 15 s"),
    "campaign --rig paper-thermal --blows 20000": ("campaign --rig paper-thermal --blows 2000",
                                                   "the same code path as 20,000 blows"),
    "prepare-offline --out carry": ("prepare-offline --out carry --platforms x86_64-linux",
                                    "CVODE for five platforms takes minutes from an empty cache"),
}
#: commands a page shows that fail today through a defect of pdbfs, not of the page:
#: run, and expected to fail until the defect is fixed (then the test says to remove
#: the entry)
KNOWN_FAILURES: dict[str, str] = {}
#: commands that do not end by themselves: their options are parsed only
PARSE_ONLY = {"app": "a web server that runs until stopped; tests/test_app.py drives it"}


def pages() -> list[Path]:
    """Every page a user reads: README, CONTRIBUTING and the docs pages (not the
    generated figures' tables)."""
    docs = sorted(p for p in DOCS.rglob("*.md") if "figures" not in p.parts and "data" not in p.parts)
    return [ROOT / p for p in TOP_PAGES] + docs


def page_id(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


@dataclass
class Block:
    lang: str
    body: str
    line: int                       # the fence's line number (1-based)
    skip: str | None = None         # why it does not run
    output: list[str] = field(default_factory=list)


#: a line that includes a file whole (pymdownx.snippets), relative to docs/
SNIPPET = re.compile(r'^\s*--8<--\s+"([^"]+)"\s*$')
#: the example scripts the pages include: each runs as a script in the docs tests, at a
#: smaller size where its full one takes minutes (file -> arguments, and why)
EXAMPLES = DOCS / "examples"
EXAMPLE_ARGS = {
    "calibration_design.py": (["--map-n", "3"], "the 21 x 21 design map is 441 simulations"),
    "closed_loop.py": (["--steps", "5e-5,2.5e-5"], "five steps down to 3.125 us take minutes"),
    "hydraulics.py": ([], ""),
    "fatigue_campaign.py": (["--blows", "2000"], "two campaigns of 20,000 blows take 20 s"),
}


def _expanded(body: list[str]) -> list[str]:
    """A block's lines with each snippet line replaced by the file it includes."""
    out = []
    for line in body:
        m = SNIPPET.match(line)
        out += (DOCS / m.group(1)).read_text().splitlines() if m else [line]
    return out


def blocks(text: str) -> list[Block]:
    """The fenced blocks of a Markdown text (indented ones dedented, included
    files in them as the page shows them)."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = re.match(r"^(\s*)```(\S*)\s*$", lines[i])
        if not m:
            i += 1
            continue
        indent, lang, start = m.group(1), m.group(2), i
        body = []
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            body.append(lines[i][len(indent):] if lines[i].startswith(indent) else lines[i])
            i += 1
        before = "\n".join(lines[max(0, start - 3):start])
        skip = SKIP.findall(before)
        body = _expanded(textwrap.dedent("\n".join(body)).splitlines())
        out.append(Block(lang, "\n".join(body) + "\n", start + 1,
                         skip[-1] if skip else None))
        i += 1
    return out


def python_blocks(text: str) -> list[Block]:
    return [b for b in blocks(text) if b.lang == "python"]


@dataclass
class Command:
    line: str                       # as shown (whitespace normalised)
    refused: bool                   # the page shows it refused (pdbfs: error:)
    skip: str | None


def commands(text: str) -> list[Command]:
    """The pdbfs commands of a page's bash and console blocks, in order."""
    out = []
    for b in blocks(text):
        if b.lang not in ("bash", "console", "sh", "shell"):
            continue
        joined = b.body.replace("\\\n", " ")
        for raw in joined.splitlines():
            if b.lang == "console" and not raw.startswith("$ "):
                if raw.startswith("pdbfs: error:") and out:
                    out[-1].refused = True
                continue
            line = raw[2:] if raw.startswith("$ ") else raw
            line = re.split(r"\s+#|^\s*#", line)[0].strip()
            if line.startswith("pdbfs "):
                out.append(Command(re.sub(r"\s+", " ", line), False, b.skip))
    return out


def as_run(line: str) -> tuple[list[str], list[str]]:
    """The command's arguments as run here, and the reasons of any size changed."""
    why = []
    for shown, (run, reason) in OVERRIDES.items():
        if shown in line:
            line, _ = line.replace(shown, run), why.append(reason)
    return shlex.split(line)[1:], why


def build_site(out: Path) -> subprocess.CompletedProcess:
    """`mkdocs build --strict` of the docs into ``out`` (the theme's banner off)."""
    import os
    return subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f",
                           str(ROOT / "mkdocs.yml"), "-d", str(out)], capture_output=True,
                          text=True, cwd=ROOT, timeout=600,
                          env={**os.environ, "NO_MKDOCS_2_WARNING": "1"})


def pdbfs(args, cwd, timeout=900):
    """Run the command line as a user would (a new process)."""
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=timeout)
