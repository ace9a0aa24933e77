#!/usr/bin/env bash
# Refreshes the native plugins committed in the Unity package (bindings/csharp/unity/Plugins/x86_64):
#
#   bash scripts/update_unity_plugins.sh [LIBDIR] [DLL]
#
# LIBDIR: a directory holding a CPU build of libpbf.so (default: builds one into build-unity-plugins/
#         with CMake: Release, PBF_WITH_CUDA=OFF, library target only).
# DLL:    the mingw-w64 pbf.dll (default: build-mingw/lib/pbf.dll, built with
#         scripts/build_windows_dll.sh when that script exists and the DLL does not).
# Then it strips both, writes any missing .meta file (fixed GUIDs from the path) and the provenance
# table in Plugins/x86_64/README.md (sha256, version, source commit), and runs
# scripts/check_unity_package.sh. Commit the result. Run it after every change to native/,
# include/ or the CMake build that a release should carry: the check warns when the plugins are
# older than the sources, and fails when their exports or version differ from the header's.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
pkg="bindings/csharp/unity"
dest="$pkg/Plugins/x86_64"

libdir="${1:-}"
if [ -z "$libdir" ]; then
  cmake -S . -B build-unity-plugins -DCMAKE_BUILD_TYPE=Release -DPBF_WITH_CUDA=OFF \
        -DPBF_BUILD_TESTS=OFF -DPBF_BUILD_SAMPLES=OFF >/dev/null
  cmake --build build-unity-plugins -j"${PBF_JOBS:-2}" --target pbf
  libdir=build-unity-plugins/lib
fi
source scripts/native_libs.sh
so="$(find_libpbf "$libdir")"
[ -n "$so" ] || { echo "update_unity_plugins.sh: no libpbf.so in $libdir" >&2; exit 2; }
copy_stripped "$so" "$dest/libpbf.so"
echo "Plugins/x86_64/libpbf.so <- $so"

dll="${2:-build-mingw/lib/pbf.dll}"
if [ ! -f "$dll" ] && [ -z "${2:-}" ] && [ -f scripts/build_windows_dll.sh ]; then
  bash scripts/build_windows_dll.sh build-mingw
fi
if [ -f "$dll" ]; then
  copy_stripped "$dll" "$dest/pbf.dll"
  echo "Plugins/x86_64/pbf.dll <- $dll"
else
  echo "update_unity_plugins.sh: WARNING: no $dll (and no scripts/build_windows_dll.sh to build it):" >&2
  echo "  Plugins/x86_64/pbf.dll left as it was ($( [ -f "$dest/pbf.dll" ] && echo present || echo ABSENT ))" >&2
fi

python3 scripts/pbf_packages.py unity-metas "$pkg" --write
python3 scripts/pbf_packages.py unity-provenance "$pkg"
bash scripts/check_unity_package.sh
