#!/usr/bin/env bash
# Refreshes the native plugins committed in the Unity package (bindings/csharp/unity/Plugins/x86_64):
#
#   bash scripts/update_unity_plugins.sh [LIBDIR] [DLL]
#
# LIBDIR: a directory holding a build of libpbf.so with both backends (default: builds one into
#         build-unity-plugins/ with CMake: Release, CUDA for every architecture of
#         PBF_CUDA_ARCHITECTURES' release default unless that variable is set, library target only).
# DLL:    the MinGW-w64 pbf.dll (default: built into build-mingw-plugins/ by
#         scripts/build_windows_dll.sh with the fatbin of LIBDIR's build, so that both plugins
#         carry the same kernels; PBF_CUDA_FATBIN names another).
# Then it strips both, writes any missing .meta file (fixed GUIDs from the path) and the provenance
# table in Plugins/x86_64/README.md (sha256, version, source commit), and runs
# scripts/check_unity_package.sh. Commit the result once per release, with the version bump: each
# committed refresh adds the plugins' size to every clone. The check warns when the plugins are
# older than the sources, and fails when their exports or version differ from the header's, when
# one lacks the kernels or links a CUDA library, or when the two carry different kernels.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
pkg="bindings/csharp/unity"
dest="$pkg/Plugins/x86_64"

libdir="${1:-}"
if [ -z "$libdir" ]; then
  # The release's architectures (CMakeLists.txt's default), not whatever the folder cached.
  archs=(-UPBF_CUDA_ARCHITECTURES)
  [ -n "${PBF_CUDA_ARCHITECTURES:-}" ] && archs=(-DPBF_CUDA_ARCHITECTURES="$PBF_CUDA_ARCHITECTURES")
  cmake -S . -B build-unity-plugins -DCMAKE_BUILD_TYPE=Release -DPBF_WITH_CUDA=ON "${archs[@]}" \
        -DPBF_BUILD_TESTS=OFF -DPBF_BUILD_SAMPLES=OFF >/dev/null
  cmake --build build-unity-plugins -j"${PBF_JOBS:-2}" --target pbf
  libdir=build-unity-plugins/lib
fi
source scripts/native_libs.sh
so="$(find_libpbf "$libdir")"
[ -n "$so" ] || { echo "update_unity_plugins.sh: no libpbf.so in $libdir" >&2; exit 2; }
copy_stripped "$so" "$dest/libpbf.so"
echo "Plugins/x86_64/libpbf.so <- $so"

dll="${2:-}"
if [ -z "$dll" ]; then
  fatbin="${PBF_CUDA_FATBIN:-$libdir/../pbf_kernels.fatbin}"
  [ -f "$fatbin" ] || { echo "update_unity_plugins.sh: no fatbin $fatbin for pbf.dll (set PBF_CUDA_FATBIN)" >&2; exit 2; }
  PBF_CUDA_FATBIN="$fatbin" PBF_JOBS="${PBF_JOBS:-2}" bash scripts/build_windows_dll.sh build-mingw-plugins
  dll=build-mingw-plugins/lib/pbf.dll
fi
copy_stripped "$dll" "$dest/pbf.dll"
echo "Plugins/x86_64/pbf.dll <- $dll"

python3 scripts/pbf_packages.py unity-metas "$pkg" --write
python3 scripts/pbf_packages.py unity-provenance "$pkg"
bash scripts/check_unity_package.sh
