#!/usr/bin/env bash
# Install pdbfs and what it needs on a fresh machine (idempotent).
# Python packages from PyPI; SUNDIALS' static archives for the FMU from Debian.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install --quiet --disable-pip-version-check -e ".[test]"
# SUNDIALS (CVODE) for the FMU's embedded solver: fetched once into a cache
python3 -c "from pdbfs.fmu.sundials import find_sundials; print('SUNDIALS:', find_sundials())"
