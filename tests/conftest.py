import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

#: the files that take longest (scripts/test.sh runs each file on one worker, in the
#: order collected): started first, so that no worker is left with one of them at the end
SLOWEST_FILES = ("test_windows_wine.py", "test_large_rigs.py", "test_fmu_platforms.py",
                 "test_fmu_sources.py", "test_fmu_symbols.py", "test_fmu_libm.py",
                 "test_no_compiler.py", "test_wheel_install.py", "test_docs.py",
                 "test_app_page.py", "test_elastic_bar.py", "test_fmu_erk.py")


def pytest_collection_modifyitems(items):
    rank = {name: i for i, name in enumerate(SLOWEST_FILES)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))   # stable: order kept


@pytest.fixture(autouse=True)
def _work_in_a_temporary_folder(tmp_path, monkeypatch):
    """Each test runs in a folder of its own: a command that writes to the
    current folder by default never writes into the repo."""
    monkeypatch.chdir(tmp_path)
