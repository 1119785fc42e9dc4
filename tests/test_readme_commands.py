"""Every shell command README.md shows runs as shown.

The synopsis lines (with [OPTIONS], NAME=LO:HI, a|b) are checked against
each command's --help: every option they name exists. The example commands
run in a temporary folder in which `docs` points at the repository's (README
names files there, as from the repository's root). Most run exactly as
written; the few whose size makes them minutes long run with a smaller size
(OVERRIDES, each justified), so that they still go through the same code.
"""
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()

#: shown size -> size run here, and why
OVERRIDES = {
    "lhs:100000": ("lhs:64", "100,000 points take about a minute on two cores"),
    "mc:10000": ("mc:64", "the same code path as 10,000 draws"),
    "--n 4096": ("--n 8", "N (D + 2) = 20,480 simulations, several minutes"),
    "--out out": ("--out out --n 5", "the default 21 x 21 map is 441 simulations"),
}
#: commands that do not end by themselves: their options are parsed only
PARSE_ONLY = {"app": "a web server that runs until stopped; tests/test_app.py drives it"}
#: not pdbfs: installs packages and runs the whole suite (CI runs scripts/test.sh itself)
NOT_RUN = ("bash scripts/",)


def blocks(text):
    """(language, lines) of each fenced code block."""
    out, lang, body = [], None, None
    for line in text.splitlines():
        if line.startswith("```"):
            if body is None:
                lang, body = line[3:].strip(), []
            else:
                out.append((lang, body))
                body = None
        elif body is not None:
            body.append(line)
    return out


def shell_lines():
    """Logical lines of README's unlabelled code blocks that start with pdbfs:
    continuations (a trailing backslash, or an indented line of more options)
    joined, prompts and trailing comments removed."""
    out = []
    for lang, body in blocks(README):
        if lang:
            continue
        text = "\n".join(body).replace("\\\n", " ")
        for raw in text.splitlines():
            line = re.split(r"\s{2,}#|^\s*#", raw)[0].strip()
            line = line[2:] if line.startswith("$ ") else line
            if line.startswith("pdbfs "):
                out.append(line)
            elif out and raw[:1].isspace() and line.startswith(("[", "--")):
                out[-1] += " " + line
            elif line.startswith("pdbfs: error:") and out:
                REFUSED[re.sub(r"\s+", " ", out[-1])] = line[len("pdbfs: error:"):].strip()
            elif line.startswith("pdbfs:") or line.startswith(NOT_RUN) or not line:
                continue            # printed output, or set-up scripts (see NOT_RUN)
    return [re.sub(r"\s+", " ", ln) for ln in out]


#: examples README shows refused (a "pdbfs: error:" line after them): the error they print
REFUSED: dict = {}


def is_synopsis(line):
    return bool(re.search(r"[\[\]|]|\.\.\.|[A-Z]{2,}", line.replace("FILE.csv", "FILE")))


LINES = shell_lines()
SYNOPSES = [ln for ln in LINES if is_synopsis(ln)]
EXAMPLES = [ln for ln in LINES if not is_synopsis(ln)]


def test_readme_shows_both_kinds():
    assert len(SYNOPSES) >= 10 and len(EXAMPLES) >= 8


def pdbfs(args, cwd, timeout=600):
    return subprocess.run([sys.executable, "-m", "pdbfs.cli", *args], capture_output=True,
                          text=True, cwd=cwd, timeout=timeout)


def help_of(command):
    """The --help text of a command, from the parser itself (no process)."""
    import argparse

    from pdbfs.cli import build_parser
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    assert command in sub.choices, f"README shows an unknown command {command!r}"
    return sub.choices[command].format_help()


@pytest.mark.parametrize("line", SYNOPSES)
def test_every_option_of_the_synopsis_exists(line):
    command = line.split()[1]
    text = help_of(command)
    for option in re.findall(r"(?<![\w-])(--?[a-z][\w-]*)", line):
        assert re.search(rf"(?<![\w-]){re.escape(option)}\b", text), (option, command)


def as_run(line):
    """The command as run here (README's size unless OVERRIDES says otherwise)."""
    for shown, (run, _why) in OVERRIDES.items():
        if shown in line:
            line = line.replace(shown, run)
    return line.split()[1:]


@pytest.mark.parametrize("line", EXAMPLES)
def test_every_example_runs(line, tmp_path):
    (tmp_path / "docs").symlink_to(ROOT / "docs")
    args = as_run(line)
    if args[0] in PARSE_ONLY:
        assert pdbfs([args[0], "--help"], tmp_path).returncode == 0
        return
    r = pdbfs(args, tmp_path)
    if line in REFUSED:               # shown refused: one line, exit 2, as README prints it
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert re.sub(r"\s+", " ", r.stderr).startswith("pdbfs: error: " + REFUSED[line])
        return
    assert r.returncode == 0, f"{line}\n{r.stderr}"
    assert "Traceback" not in r.stderr
    if "--json" in args:
        import json
        json.loads(r.stdout)
