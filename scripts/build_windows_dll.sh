#!/usr/bin/env bash
# Cross-builds the CPU-backend pbf.dll for 64-bit Windows with MinGW-w64 (no CUDA):
#
#   bash scripts/build_windows_dll.sh [BUILD_DIR=build-mingw] [TARGET...]
#
# Output: BUILD_DIR/lib/pbf.dll (with its import library BUILD_DIR/libpbf.dll.a). The DLL
# exports the pbf_* functions only (__cdecl, declared PBF_API in include/pbf_c_api.h) and links
# libgcc, libstdc++, libgomp (OpenMP) and winpthreads statically: it needs no MinGW runtime DLL,
# only Windows' own (KERNEL32.dll, msvcrt.dll and the like). The script checks both and fails
# otherwise. TARGETs (default: pbf) are built as well, e.g. pbf_api_tests.
#
# Uses cmake/mingw-w64-x86_64.cmake; installs g++-mingw-w64-x86-64-posix (Debian/Ubuntu) when
# missing. The C API tests are built and run under Wine by scripts/check_windows.sh.
# Environment: PBF_JOBS (build parallelism, default nproc).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${1:-build-mingw}"
shift || true
targets=(pbf "$@")
triple=x86_64-w64-mingw32

if ! command -v "$triple-g++-posix" >/dev/null 2>&1; then
  bash "$root/scripts/install-deps.sh" windows
fi
command -v "$triple-g++-posix" >/dev/null 2>&1 || { echo "build_windows_dll.sh: $triple-g++-posix not found" >&2; exit 1; }

# Catch2 v2 is one header; the tests get a directory holding only it (see tests/CMakeLists.txt).
case "$build" in /*) build_abs="$build" ;; *) build_abs="$root/$build" ;; esac
catch_dir="$build_abs/catch2-include"
if [ -f /usr/include/catch2/catch.hpp ]; then
  mkdir -p "$catch_dir/catch2"
  cp -u /usr/include/catch2/catch.hpp "$catch_dir/catch2/"
fi
eigen_dir="$(dirname "$(find /usr/share/eigen3/cmake /usr/lib/cmake/eigen3 /usr/share/cmake/eigen3 -name Eigen3Config.cmake 2>/dev/null | head -n 1)")"

cmake -S "$root" -B "$build" \
  -DCMAKE_TOOLCHAIN_FILE="$root/cmake/mingw-w64-x86_64.cmake" \
  -DCMAKE_BUILD_TYPE=Release \
  -DPBF_WITH_CUDA=OFF \
  -DPBF_BUILD_SAMPLES=OFF \
  -DPBF_BUILD_TESTS=ON \
  -DPBF_CATCH2_INCLUDE_DIR="$catch_dir" \
  -DEigen3_DIR="$eigen_dir"
cmake --build "$build" --target "${targets[@]}" -j"${PBF_JOBS:-$(nproc)}"

dll="$build/lib/pbf.dll"
[ -f "$dll" ] || { echo "build_windows_dll.sh: $dll was not built" >&2; exit 1; }
dump="$("$triple-objdump" -p "$dll")"
# Exported names: the rows of the export name table, "[ n] name".
exports="$(awk '/\[Ordinal\/Name Pointer\] Table/ {t = 1; next} t && /^[ \t]*\[ *[0-9]+\]/ {print $NF; next} t && NF == 0 {t = 0}' <<<"$dump")"
count="$(grep -c . <<<"$exports" || true)"
others="$(grep -v '^pbf_' <<<"$exports" || true)"
if [ "$count" -eq 0 ] || [ -n "$others" ]; then
  echo "build_windows_dll.sh: $dll exports $count names, these not pbf_*:" >&2
  echo "${others:-(none exported)}" | head -20 >&2
  exit 1
fi
# ... and every function the header declares is among them.
declared="$(grep -oE 'PBF_CALL[[:space:]]+pbf_[a-z0-9_]+[[:space:]]*\(' include/pbf_c_api.h | grep -oE 'pbf_[a-z0-9_]+' | sort -u)"
absent="$(comm -23 <(echo "$declared") <(sort -u <<<"$exports") | tr '\n' ' ')"
if [ -n "${absent// /}" ]; then
  echo "build_windows_dll.sh: $dll does not export: $absent" >&2
  exit 1
fi
imports="$(awk '/DLL Name:/ {print $3}' <<<"$dump" | sort -u | paste -sd ' ')"
if grep -q -i -E 'libgcc|libstdc\+\+|libgomp|libwinpthread' <<<"$imports"; then
  echo "build_windows_dll.sh: $dll needs MinGW runtime DLLs: $imports" >&2
  exit 1
fi
echo "build_windows_dll.sh: $dll ($(stat -c %s "$dll") bytes): $count exports, all pbf_*; imports $imports"
