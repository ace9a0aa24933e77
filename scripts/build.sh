#!/usr/bin/env bash
# Configures and builds libpbf, its tests and samples (Release):
#
#   scripts/build.sh [BUILD_DIR=build] [TARGET...]
#
# With TARGETs (e.g. dam_break), only those and what they need are built; without, everything.
#
# Environment:
#   PBF_CUDA_ARCHITECTURES  CUDA architectures to build for (default here: 90, one architecture
#                           for a quick build; CMake's own default is the full release list)
#   PBF_WITH_CUDA           OFF to build without the CUDA backend (default ON: the CUDA backend
#                           is built whenever nvcc is found)
# Missing Debian packages are installed first (scripts/install-deps.sh).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build_dir="${1:-build}"
shift || true
targets=()
[ "$#" -gt 0 ] && targets=(--target "$@")

bash "$root/scripts/install-deps.sh"

# CMake finds nvcc on PATH (or through CUDACXX); the CUDA toolkit's usual place is not on it.
if [ -z "${CUDACXX:-}" ] && ! command -v nvcc >/dev/null 2>&1 && [ -x /usr/local/cuda/bin/nvcc ]; then
  export PATH="/usr/local/cuda/bin:$PATH"
fi

case "${PBF_WITH_CUDA:-ON}" in
  OFF | Off | off | 0 | NO | No | no | FALSE | False | false) with_cuda=OFF ;;
  *) with_cuda=ON ;;
esac

cmake -S "$root" -B "$build_dir" \
  -DCMAKE_BUILD_TYPE=Release \
  -DPBF_WITH_CUDA="$with_cuda" \
  -DPBF_WARNINGS_AS_ERRORS="${PBF_WARNINGS_AS_ERRORS:-OFF}" \
  -DPBF_CUDA_ARCHITECTURES="${PBF_CUDA_ARCHITECTURES:-90}"
cmake --build "$build_dir" "${targets[@]}" -j"$(nproc)"
