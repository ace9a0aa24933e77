#!/usr/bin/env bash
# Cross-builds pbf.dll for 64-bit Windows with MinGW-w64: one DLL with both backends, the CPU
# (on the Windows thread pool) and CUDA, whose kernels (a fatbin) are embedded in it:
#
#   bash scripts/build_windows_dll.sh [BUILD_DIR=build-mingw] [TARGET...]
#
# Output: BUILD_DIR/lib/pbf.dll (with its import library BUILD_DIR/libpbf.dll.a). The CUDA
# backend's host code is plain C++ over the CUDA driver API: the DLL opens nvcuda.dll (from
# System32) at run time, so it imports no CUDA DLL and loads on machines without an NVIDIA driver.
# It takes cuda.h from the CUDA toolkit here (the Linux one: the driver API's declarations are the
# same), searched after MinGW's own headers. The kernels are the same for every OS: PBF_CUDA_FATBIN
# names a fatbin to embed (e.g. build/pbf_kernels.fatbin of a Linux build, as CI and
# scripts/update_unity_plugins.sh do); without it, nvcc builds one here for PBF_CUDA_ARCHITECTURES.
#
# The script checks the DLL and fails otherwise (scripts/pbf_packages.py check-native): it exports
# exactly the header's pbf_* functions (__cdecl, PBF_API); it imports only Windows' own DLLs
# (libgcc, libstdc++ and winpthreads are linked in; no nvcuda.dll, no cudart); it
# carries the fatbin. The last line gives its size. TARGETs (default: pbf) are built as well,
# e.g. pbf_api_tests.
#
# Uses cmake/mingw-w64-x86_64.cmake; installs g++-mingw-w64-x86-64-posix (Debian/Ubuntu) when
# missing. The C API tests are built and run under Wine by scripts/check_windows.sh.
# Environment:
#   PBF_CUDA_FATBIN         a prebuilt fatbin to embed (default: nvcc builds one here)
#   PBF_CUDA_ARCHITECTURES  architectures nvcc builds for without PBF_CUDA_FATBIN (default 90, as
#                           scripts/build.sh; CMakeLists.txt lists the release set)
#   PBF_WITH_CUDA           OFF for a CPU-only DLL (then checked to carry no kernels)
#   PBF_WITH_INTEROP        OFF leaves the graphics interop out (default ON)
#   PBF_JOBS                build parallelism (default nproc)
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

case "${PBF_WITH_CUDA:-ON}" in
  OFF | Off | off | 0 | NO | No | no | FALSE | False | false) with_cuda=OFF ;;
  *) with_cuda=ON ;;
esac
fatbin="${PBF_CUDA_FATBIN:-}"
if [ -n "$fatbin" ]; then
  [ -f "$fatbin" ] || { echo "build_windows_dll.sh: PBF_CUDA_FATBIN=$fatbin: no such file" >&2; exit 1; }
  fatbin="$(cd "$(dirname "$fatbin")" && pwd)/$(basename "$fatbin")"
fi

cmake -S "$root" -B "$build" \
  -DCMAKE_TOOLCHAIN_FILE="$root/cmake/mingw-w64-x86_64.cmake" \
  -DCMAKE_BUILD_TYPE=Release \
  -DPBF_WITH_CUDA="$with_cuda" \
  -DPBF_WARNINGS_AS_ERRORS="${PBF_WARNINGS_AS_ERRORS:-OFF}" \
  -DPBF_CUDA_FATBIN="$fatbin" \
  -DPBF_CUDA_ARCHITECTURES="${PBF_CUDA_ARCHITECTURES:-90}" \
  -DPBF_WITH_INTEROP="${PBF_WITH_INTEROP:-ON}" \
  -DPBF_BUILD_SAMPLES=OFF \
  -DPBF_BUILD_TESTS=ON \
  -DPBF_CATCH2_INCLUDE_DIR="$catch_dir" \
  -DEigen3_DIR="$eigen_dir"
cmake --build "$build" --target "${targets[@]}" -j"${PBF_JOBS:-$(nproc)}"

dll="$build/lib/pbf.dll"
[ -f "$dll" ] || { echo "build_windows_dll.sh: $dll was not built" >&2; exit 1; }
gpu=required
[ "$with_cuda" = ON ] || gpu=absent
if ! check="$(python3 "$root/scripts/pbf_packages.py" check-native "$dll" win-x64 "$gpu")"; then
  echo "$check" >&2
  echo "build_windows_dll.sh: $dll fails its checks" >&2
  exit 1
fi
imports="$(python3 "$root/scripts/pbf_packages.py" deps "$dll" | paste -sd ' ')"
exports="$(python3 "$root/scripts/pbf_packages.py" exports "$dll" | grep -c .)"
kernels="$(sed -n -E 's/.*carries libpbf.s CUDA kernels: (.*)$/\1/p' <<<"$check")"
echo "build_windows_dll.sh: $dll ($(stat -c %s "$dll") bytes, CPU${kernels:+ and CUDA: $kernels}): $exports exports, all pbf_*; imports $imports"
