#!/usr/bin/env bash
# The dependency floors pyproject.toml declares, tested: a virtual environment
# (.venv-floor) with each floor pinned (scripts/floor-constraints.txt: numpy 1.24,
# scipy 1.10, casadi 3.6, pandas 1.5, ...), then the core of the test suite in it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >/dev/null          # the optional test tools and the CVODE build
[ -x .venv-floor/bin/python ] || python3 -m venv .venv-floor
.venv-floor/bin/python -m pip install --quiet --disable-pip-version-check \
    -c scripts/floor-constraints.txt -e . pytest
.venv-floor/bin/python -c "import numpy, scipy, casadi, pandas; print('floor:', 'numpy', \
numpy.__version__, 'scipy', scipy.__version__, 'casadi', casadi.__version__, 'pandas', pandas.__version__)"
.venv-floor/bin/python -m pytest -q -p no:cacheprovider "$@" tests/test_paper_rig.py \
    tests/test_core.py tests/test_physics.py tests/test_compiled.py tests/test_calibration.py \
    tests/test_sweep.py tests/test_no_silent_errors.py
