#!/usr/bin/env bash
# The C and C++ sources are formatted by clang-format with .clang-format: fails, naming the files
# and showing the first differences, where one is not. `scripts/check_format.sh --fix` formats
# them in place. Left alone: the public header (its tables are laid out by hand for readers) and
# generated files. Needs clang-format (installed with apt-get when missing; skipped, not failed,
# where it cannot be).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.." || exit 1
fix=0
[ "${1:-}" = "--fix" ] && fix=1
if ! command -v clang-format >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  { $sudo apt-get install -y -q clang-format || { $sudo apt-get update -q && $sudo apt-get install -y -q clang-format; }; } \
    >/dev/null 2>&1 || true
fi
command -v clang-format >/dev/null 2>&1 || { echo "check_format.sh: skipped: no clang-format"; exit 0; }
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cpp' '*.cu' '*.cuh' |
  grep -v -E '^include/pbf_c_api\.h$|^bindings/csharp/tools/layout_dump\.c$')
if [ "$fix" -eq 1 ]; then
  clang-format -i "${files[@]}"
  echo "check_format.sh: formatted ${#files[@]} files"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ "${#bad[@]}" -gt 0 ]; then
  echo "check_format.sh: FAILED: ${#bad[@]} of ${#files[@]} files differ from clang-format ($(clang-format --version | head -1)):"
  printf '  %s\n' "${bad[@]}" | head -20
  clang-format --dry-run "${bad[0]}" 2>&1 | head -20
  echo "check_format.sh: run scripts/check_format.sh --fix"
  exit 1
fi
echo "check_format.sh: ok: ${#files[@]} files as clang-format formats them"
