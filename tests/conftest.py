import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(autouse=True)
def _work_in_a_temporary_folder(tmp_path, monkeypatch):
    """Each test runs in a folder of its own: a command that writes to the
    current folder by default (simulate's out/) never writes into the repo."""
    monkeypatch.chdir(tmp_path)
