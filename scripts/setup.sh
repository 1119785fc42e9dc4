#!/usr/bin/env bash
# Install pdbfs and what it needs on a fresh machine (idempotent).
# Python packages from PyPI; SUNDIALS' CVODE built once with SUNDIALS' own
# CMake from Debian's source (pdbfs/native/build_sundials.sh, cached in
# ~/.cache/pdbfs/sundials-cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m pip install --quiet --disable-pip-version-check -e ".[test]"

as_root_apt() {   # apt-get needs root; CI runs as root
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then "$@"; else return 1; fi
}
# the build needs cmake and a C compiler; the source comes through apt's lists
if ! command -v cmake >/dev/null; then
    as_root_apt apt-get update -qq || true
    as_root_apt apt-get install -y -qq cmake >/dev/null || python3 -m pip install --quiet cmake
fi
if ! ls /var/lib/apt/lists/*Packages* >/dev/null 2>&1; then as_root_apt apt-get update -qq || true; fi
sundials() {
    python3 -c "from pdbfs.native.sundials import find_sundials; print('SUNDIALS:', find_sundials())"
}
sundials || { as_root_apt apt-get update -qq && rm -f ~/.cache/pdbfs/sundials-cmake.failed && sundials; }
