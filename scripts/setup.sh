#!/usr/bin/env bash
# Install pdbfs and what it needs on a fresh machine (idempotent).
# Python packages from PyPI; SUNDIALS for the FMU from Debian (see fmu/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install --quiet --disable-pip-version-check -e ".[test]"

sundials() {
    python3 -c "from pdbfs.fmu.sundials import find_sundials; print('SUNDIALS:', find_sundials())"
}
apt_update() {   # SUNDIALS' source and archives come through apt: its lists must be there
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then apt-get update -qq; fi
}
if ! ls /var/lib/apt/lists/*Packages* >/dev/null 2>&1; then apt_update; fi
sundials || { apt_update && sundials; }
