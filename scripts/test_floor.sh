#!/usr/bin/env bash
# The dependency floors pyproject.toml declares, tested: a virtual environment
# (.venv-floor) with each floor pinned (scripts/floor-constraints.txt: numpy 1.24,
# scipy 1.10, casadi 3.6, pandas 1.5, ..., and the extras': dash 4.0, dask 2023.1,
# pyarrow 12, SALib 1.4.7, ...), then the core of the test suite and the extras' tests in it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null          # the optional test tools and the CVODE build
[ -x .venv-floor/bin/python ] || python3 -m venv .venv-floor
# the core and the extras but [dask] (whose floor of casadi is higher: 3.7.1)
.venv-floor/bin/python -m pip install --quiet --disable-pip-version-check \
    -c scripts/floor-constraints.txt -e ".[app,parquet,sensitivity]" pytest pytest-xdist
.venv-floor/bin/python -m pip uninstall --quiet -y dask distributed 2>/dev/null || true
floor() {
    .venv-floor/bin/python -c "import importlib; print('floor:', *(f'{m} {importlib.import_module(m)\
.__version__}' for m in '$*'.split()))"
}
floor numpy scipy casadi pandas dash pyarrow SALib
.venv-floor/bin/python -m pytest -q -p no:cacheprovider -n "${PDBFS_TEST_WORKERS:-auto}" \
    --dist loadfile "$@" tests/test_paper_rig.py \
    tests/test_core.py tests/test_physics.py tests/test_compiled.py tests/test_calibration.py \
    tests/test_sweep.py tests/test_no_silent_errors.py tests/test_extras.py
# [dask] at its floors, with the casadi it needs
grep -v '^casadi==' scripts/floor-constraints.txt > .venv-floor/constraints-dask.txt
echo "casadi==3.7.1" >> .venv-floor/constraints-dask.txt
.venv-floor/bin/python -m pip install --quiet --disable-pip-version-check \
    -c .venv-floor/constraints-dask.txt -e ".[dask]"
floor casadi dask distributed
.venv-floor/bin/python -m pytest -q -p no:cacheprovider "$@" tests/test_extras.py -k dask
