"""What the installed package says about itself: its version (the same from
Python, the command line and the installed metadata), where its
documentation, source and changelog are, and, for a feature whose extra is
missing, which extra to install."""
import re
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest

import pdbfs
from pdbfs.errors import EXTRAS, MissingExtraError

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = [ROOT / "pdbfs", ROOT / "components", ROOT / "models", ROOT / "fmu"]


def test_the_version_is_the_installed_distributions():
    assert pdbfs.__version__ == metadata.version("pdbfs")
    r = subprocess.run([sys.executable, "-m", "pdbfs.cli", "--version"], capture_output=True,
                       text=True, timeout=120)
    assert r.stdout.strip() == f"pdbfs {pdbfs.__version__}", r


def test_the_metadata_names_the_documentation_source_and_changelog():
    tomllib = pytest.importorskip("tomllib")           # Python 3.11+
    urls = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["urls"]
    assert {"Documentation", "Source", "Changelog"} <= set(urls)
    assert all(u.startswith("https://") for u in urls.values()), urls
    assert urls["Changelog"].endswith("CHANGELOG.md") and urls["Changelog"].startswith(urls["Source"])
    installed = dict(e.split(", ", 1) for e in metadata.metadata("pdbfs").get_all("Project-URL") or [])
    assert installed == urls, "reinstall pdbfs (pip install -e .): its metadata is older than pyproject.toml"


def test_to_control_without_python_control_names_the_extra(monkeypatch):
    """Linearization.to_control() without python-control: the extra to install,
    as every other extra's feature says it (an ImportError, so code that
    catches that still works)."""
    from pdbfs.simulation.analysis.linearize import Linearization
    lin = Linearization(A=np.zeros((1, 1)), B=np.zeros((1, 0)), C=np.zeros((0, 1)),
                        D=np.zeros((0, 0)), states=["x"], inputs=[], outputs=[], t=0.0)
    monkeypatch.setitem(sys.modules, "control", None)         # as if it were not installed
    with pytest.raises(MissingExtraError, match=re.escape("pip install 'pdbfs[control]'")):
        lin.to_control()
    with pytest.raises(ImportError):
        lin.to_control()


def test_every_install_hint_of_the_package_names_an_extra_or_a_core_dependency():
    """A message that says `pip install X` names an extra (`pdbfs[NAME]`, a
    real one) or a package pdbfs depends on; never a bare optional package
    (which installs a version pdbfs was not tested with)."""
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = {re.split(r"[<>=!~\[; ]", d, maxsplit=1)[0].lower() for d in project["dependencies"]}
    extras = set(project["optional-dependencies"])
    assert set(EXTRAS) <= extras
    hints = []
    for folder in PACKAGE:
        for path in folder.rglob("*.py"):
            for m in re.finditer(r"pip install ([^\s`\"')]+|['\"][^'\"]+['\"])", path.read_text()):
                hints.append((path.relative_to(ROOT).as_posix(), m.group(1).strip("'\"")))
    assert hints
    for where, target in hints:
        if target.startswith("-") or re.search(r"\{|\.\.\.", target):   # an option, a placeholder
            continue
        extra = re.fullmatch(r"pdbfs\[([a-z,]+)\]", target)
        if extra:
            assert set(extra.group(1).split(",")) <= extras, (where, target)
        else:
            assert target.lower() in core, f"{where}: 'pip install {target}' names no extra"
