#!/usr/bin/env bash
# Install pdbfs and what it needs on a fresh machine (idempotent).
# Without an active virtual environment, one is made in .venv (a stock Debian
# Python refuses pip installs into itself: PEP 668). Python packages come from
# PyPI; Debian packages (cmake, the venv module) with apt-get when root;
# SUNDIALS' CVODE is built once with its own CMake from Debian's source
# (pdbfs/native/build_sundials.sh, cached in ${XDG_CACHE_HOME:-~/.cache}/pdbfs).
# Source scripts/env.sh afterwards to use the environment (test.sh, main.sh do).
set -euo pipefail
cd "$(dirname "$0")/.."
# each step says what it does and how long it took (a fresh machine needs minutes)
SECONDS=0
step() { echo "setup [${SECONDS} s]: $*" >&2; }

as_root_apt() {   # apt-get needs root; CI runs as root
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then "$@"; else return 1; fi
}
apt_install() {
    if ! ls /var/lib/apt/lists/*Packages* >/dev/null 2>&1; then as_root_apt apt-get update -qq || true; fi
    as_root_apt env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null \
        || { as_root_apt apt-get update -qq && as_root_apt env DEBIAN_FRONTEND=noninteractive \
             apt-get install -y -qq "$@" >/dev/null; }
}

if [ -z "${VIRTUAL_ENV:-}" ] && [ ! -x .venv/bin/python ]; then
    step "making the virtual environment .venv"
    python3 -m venv .venv 2>/dev/null || { rm -rf .venv; apt_install python3-venv && python3 -m venv .venv; }
fi
source scripts/env.sh
step "installing pdbfs and its Python packages (pip; a few minutes the first time)"
python -m pip install --quiet --disable-pip-version-check -e ".[test]"

# the browser tests of `pdbfs app` drive Debian's Chromium through its chromedriver
if ! [ -x /usr/bin/chromium ] || ! [ -x /usr/bin/chromedriver ]; then
    step "installing Chromium and its driver (apt-get)"
    apt_install chromium chromium-driver || echo "setup: chromium not installed (needs root): the browser tests will be skipped"
fi

# the build needs cmake and a C compiler; the source comes through apt's lists
if ! command -v cmake >/dev/null; then step "installing cmake"; apt_install cmake || python -m pip install --quiet cmake; fi
# win64 FMU binaries: MinGW-w64; running them in the tests: Wine (package wine64
# holds the loader /usr/lib/wine/wine64, package wine the `wine` command);
# ecospy's bundled binaries need Intel TBB
if ! command -v x86_64-w64-mingw32-gcc >/dev/null || [ ! -x /usr/lib/wine/wine64 ] \
        || ! ldconfig -p 2>/dev/null | grep -q libtbb.so.12; then
    step "installing MinGW-w64, Wine and libtbb12 (apt-get; the largest download)"
    apt_install gcc-mingw-w64-x86-64 wine wine64 libtbb12 || echo "setup: could not install MinGW-w64, Wine" \
        "or libtbb12 (needs root): no win64 binaries in FMUs, their tests are skipped" >&2
fi
if ! ls /var/lib/apt/lists/*Packages* >/dev/null 2>&1; then as_root_apt apt-get update -qq || true; fi
sundials() {
    python -c "from pdbfs.native.sundials import find_sundials; print('SUNDIALS:', find_sundials())"
}
failed_marker() {
    python -c "from pdbfs.native.sundials import failed_marker; print(failed_marker())"
}
step "finding or building SUNDIALS' CVODE (built once, about 10 s per platform)"
sundials || { as_root_apt apt-get update -qq && rm -f "$(failed_marker)" && sundials; }
if command -v x86_64-w64-mingw32-gcc >/dev/null; then   # the win64 CVODE and the sources, built once
    python -c "from pdbfs.native.sundials import find_sundials; print('SUNDIALS win64:', find_sundials(target='win64').origin)" || true
fi
python -c "from pdbfs.native.sundials import find_sundials_sources; print('SUNDIALS sources:', find_sundials_sources().root)" || true
step "done"
