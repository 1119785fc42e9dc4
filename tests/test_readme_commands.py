"""README.md as a front door: short, its commands run, its install commands
are the ones CI runs, the extras it names exist.

(Every page's commands, README's included, also run in tests/test_docs.py;
here are the checks only README needs.)"""
import re

import pytest

import docs_examples as D

ROOT = D.ROOT
README = (ROOT / "README.md").read_text()


def test_readme_is_a_front_door():
    lines = README.splitlines()
    assert 150 <= len(lines) <= 250, len(lines)
    for heading in ("## Install", "## What it can do", "## Speed", "## Citing"):
        assert heading in lines, heading
    assert "![" in README and "docs/figures/" in README          # a picture of the pulse


def test_readme_shows_python_and_the_command_line():
    assert len(D.python_blocks(README)) == 1
    assert 3 <= len(D.commands(README)) <= 4


def test_the_install_commands_are_the_scripts_ci_runs():
    shown = re.findall(r"^bash (scripts/\S+\.sh)", README, flags=re.M)
    assert shown == ["scripts/main.sh", "scripts/test.sh"]
    for script in shown:
        assert (ROOT / script).is_file()
    assert "bash scripts/test.sh" in (ROOT / ".ci" / "run").read_text()


def test_the_extras_readme_names_exist():
    named = set(re.findall(r"`\[(\w+)\]`", README)) | set(re.findall(r'pdbfs\[(\w+)\]', README))
    assert {"all", "app", "dask", "parquet", "sensitivity", "docs", "test"} <= named
    try:
        import tomllib
    except ImportError:                     # Python 3.10
        tomllib = pytest.importorskip("tomli")
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"].get(
        "optional-dependencies", {})
    if "all" not in declared:
        pytest.skip("pyproject.toml declares no [all] extra yet (the light core with extras)")
    assert named <= set(declared), sorted(named - set(declared))


def test_the_benchmark_table_says_machine_date_and_scripts():
    speed = README.split("## Speed", 1)[1].split("\n## ", 1)[0]
    assert re.search(r"\b20\d\d-\d\d-\d\d\b", speed)                     # the date
    assert "2-core" in speed and "Python 3." in speed                     # the machine
    for script in re.findall(r"scripts/(bench_\w+\.py)", speed):
        assert (ROOT / "scripts" / script).is_file(), script
