#!/usr/bin/env bash
# Build SUNDIALS' CVODE with SUNDIALS' own CMake and install it into PREFIX:
# static archives, position independent, -O2, CVODE only.  This is the CVODE
# that pdbfs links into FMU binaries and into the compiled backend.
#
#   build_sundials.sh PREFIX [SOURCE_TARBALL]
#
# PDBFS_SUNDIALS_TARGET=win64 cross-compiles it for 64-bit Windows with
# Debian's MinGW-w64 (x86_64-w64-mingw32-gcc) through a CMake toolchain file.
# PDBFS_SUNDIALS_TARGET=sources builds nothing: PREFIX gets the C sources that
# pdbfs links (for source FMUs), SUNDIALS' public headers and its LICENSE.
#
# Without a tarball, the source is Debian's `sundials` source package (the
# same 6.4.1 as libsundials-dev): `apt-get source` if a deb-src line exists,
# else the orig tarball from libsundials-dev's pool directory, accepted only
# with the SHA-256 pinned below.  Needs cmake, a C compiler and, to fetch,
# apt with current package lists.
set -euo pipefail
prefix=${1:?usage: build_sundials.sh PREFIX [SOURCE_TARBALL]}
tarball=${2:-}
pinned_name="sundials_6.4.1+dfsg1.orig.tar.xz"
pinned_sha256="c61157f1d4be06c704bea40cb131eb63ba2dada161989071604d0a0959cdf04a"

work=$(mktemp -d "${TMPDIR:-/tmp}/pdbfs-sundials.XXXXXX")
trap 'rm -rf "$work" "$prefix.part"' EXIT
chmod 755 "$work"   # apt's download sandbox user writes here

if [ -z "$tarball" ]; then
    (cd "$work" && apt-get source --download-only -qq sundials >/dev/null 2>&1) || true
    tarball=$(ls "$work"/sundials_*.orig.tar.* 2>/dev/null | head -n 1 || true)
fi
if [ -z "$tarball" ]; then
    uri=$(apt-get download --print-uris libsundials-dev | head -n 1 | cut -d"'" -f2)
    case "$uri" in http://*|https://*) ;; *) echo "cannot locate libsundials-dev through apt" >&2; exit 1;; esac
    tarball="$work/$pinned_name"
    /usr/lib/apt/apt-helper download-file "${uri%/*}/${pinned_name/+/%2b}" "$tarball" \
        "SHA256:$pinned_sha256" >"$work/fetch.log" 2>&1 || { cat "$work/fetch.log" >&2; exit 1; }
fi

log="$work/log"
cross=()
case "${PDBFS_SUNDIALS_TARGET:-native}" in
    native|sources) ;;
    win64)
        cat > "$work/mingw64.cmake" <<'TOOLCHAIN'
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER x86_64-w64-mingw32-gcc)
set(CMAKE_CXX_COMPILER x86_64-w64-mingw32-g++)
set(CMAKE_RC_COMPILER x86_64-w64-mingw32-windres)
set(CMAKE_FIND_ROOT_PATH /usr/x86_64-w64-mingw32)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
TOOLCHAIN
        cross=(-DCMAKE_TOOLCHAIN_FILE="$work/mingw64.cmake");;
    *) echo "unknown PDBFS_SUNDIALS_TARGET '${PDBFS_SUNDIALS_TARGET}' (native, win64 or sources)" >&2
       exit 1;;
esac
run() { "$@" >>"$log" 2>&1 || { tail -n 30 "$log" >&2; echo "failed: $*" >&2; exit 1; }; }

mkdir "$work/src"
tar -xf "$tarball" -C "$work/src" --strip-components=1
if [ "${PDBFS_SUNDIALS_TARGET:-native}" = sources ]; then
    # CVODE, serial vectors, dense and band matrices and solvers, Newton and
    # fixed point, the generic layer: what the CVODE loop links
    mkdir -p "$prefix.part/src"
    for d in cvode nvector/serial sunmatrix/dense sunmatrix/band sunlinsol/dense sunlinsol/band \
             sunnonlinsol/newton sunnonlinsol/fixedpoint sundials; do
        mkdir -p "$prefix.part/src/$d"
        cp "$work/src/src/$d"/*.[ch] "$prefix.part/src/$d/"
    done
    cp -r "$work/src/include" "$prefix.part/include"
    cp "$work/src/LICENSE" "$prefix.part/"
    echo "$(basename "$tarball"), sources" > "$prefix.part/ORIGIN"
    rm -rf "$prefix"
    mv "$prefix.part" "$prefix"
    exit 0
fi
run cmake -S "$work/src" -B "$work/build" "${cross[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
    -DBUILD_STATIC_LIBS=ON -DBUILD_SHARED_LIBS=OFF -DBUILD_CVODE=ON -DBUILD_CVODES=OFF \
    -DBUILD_ARKODE=OFF -DBUILD_IDA=OFF -DBUILD_IDAS=OFF -DBUILD_KINSOL=OFF \
    -DEXAMPLES_ENABLE_C=OFF -DEXAMPLES_INSTALL=OFF -DCMAKE_INSTALL_PREFIX="$prefix.part"
run cmake --build "$work/build" -j "$(nproc 2>/dev/null || echo 2)"
run cmake --install "$work/build"
cp "$work/src/LICENSE" "$prefix.part/" 2>/dev/null || true
echo "$(basename "$tarball"), built with SUNDIALS' CMake (Release, -O2, static, PIC)" > "$prefix.part/ORIGIN"
rm -rf "$prefix"
mv "$prefix.part" "$prefix"
