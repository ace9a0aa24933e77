#!/usr/bin/env bash
# The Windows build, checked on Linux: cross-builds the CPU-backend pbf.dll with MinGW-w64
# (scripts/build_windows_dll.sh: only pbf_* exported, no MinGW runtime DLLs needed), builds the
# Catch2 suites that run on the CPU backend for Windows, and runs them under Wine:
#
#   bash scripts/check_windows.sh [BUILD_DIR=build-mingw]
#
#   pbf_api_tests          the C ABI: versions, struct layout (tests/header_c99.c), validation,
#                          handles, capacity, mapping, logging, thread-local errors
#   pbf_reliability_tests  fuzz-finding regressions, out of memory, capacity, threads
#   pbf_unit_tests         white-box: SPH kernels, LDC, neighbour masks, colliders and the CPU
#                          scenes (resting tank, dam break, nozzles, drains), on the static core
#
# Test cases that cannot work under Windows would be excluded by Catch2 tag here (none are).
# The Wine prefix lives in BUILD_DIR/wine (created on the first run, which is the slow one);
# WINEDEBUG=-all, and Wine's Mono and Gecko installers are switched off (headless).
#
# Needs g++-mingw-w64-x86-64-posix and wine (scripts/install-deps.sh windows installs them). If
# they cannot be installed the check is skipped, not failed, and says so. The last line is the
# summary: "check_windows.sh: ok: ...", "check_windows.sh: skipped: ..." or
# "check_windows.sh: FAILED: ..."; exits non-zero only on failure.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
build="${1:-build-mingw}"
suites=(pbf_api_tests pbf_reliability_tests pbf_unit_tests)
# Catch2 test spec per suite (empty: every test case), e.g. "~[posix-only]".
declare -A spec=([pbf_api_tests]="" [pbf_reliability_tests]="" [pbf_unit_tests]="")

skip() { echo "check_windows.sh: skipped: $1"; exit 0; }
fail() { echo "check_windows.sh: FAILED: $1"; exit 1; }

if ! command -v x86_64-w64-mingw32-g++-posix >/dev/null 2>&1 || ! command -v wine >/dev/null 2>&1; then
  bash scripts/install-deps.sh windows || true
fi
command -v x86_64-w64-mingw32-g++-posix >/dev/null 2>&1 || skip "no MinGW-w64 compiler (x86_64-w64-mingw32-g++-posix) and it could not be installed"
command -v wine >/dev/null 2>&1 || skip "no wine and it could not be installed"

echo "== cross-build pbf.dll and ${suites[*]} ($build/)"
mkdir -p "$build"
build_log="$build/check_windows.build.log"
if ! bash scripts/build_windows_dll.sh "$build" "${suites[@]}" >"$build_log" 2>&1; then
  grep -E -B2 -A6 'error|Error|build_windows_dll.sh:' "$build_log" | head -60
  fail "the MinGW build ($build_log)"
fi
dll_line="$(grep -E '^build_windows_dll.sh: ' "$build_log" | tail -n 1)"
echo "$dll_line"

case "$build" in /*) build_abs="$build" ;; *) build_abs="$root/$build" ;; esac
export WINEPREFIX="$build_abs/wine"
export WINEDEBUG=-all
export WINEDLLOVERRIDES="mscoree,mshtml="  # no Mono/Gecko install dialogs
export WINEPATH="Z:$(tr '/' '\\' <<<"$build_abs/lib")"  # where pbf.dll is
unset DISPLAY
if [ ! -f "$WINEPREFIX/system.reg" ]; then
  echo "== creating the Wine prefix $WINEPREFIX (first run only)"
  wineboot --init >"$build/check_windows.wineboot.log" 2>&1
  wineserver -w 2>/dev/null || true
fi

declare -a results=()
failed=0
for suite in "${suites[@]}"; do
  exe="$build/tests/$suite.exe"
  echo
  echo "== wine $exe ${spec[$suite]}"
  log="$build/check_windows.$suite.log"
  start=$(date +%s)
  # shellcheck disable=SC2086  # the spec is one word or none
  wine "$exe" ${spec[$suite]} >"$log" 2>&1
  rc=$?
  secs=$(( $(date +%s) - start ))
  tr -d '\r' <"$log" | tail -n 3
  line="$(tr -d '\r' <"$log" | grep -E '^(All tests passed|test cases:)' | tail -n 1)"
  if [ "$rc" -ne 0 ] || [ -z "$line" ]; then
    tr -d '\r' <"$log" | grep -E -B3 -A12 'FAILED|failed' | head -60
    results+=("$suite FAILED: ${line:-no Catch2 summary} (exit $rc, $log)")
    failed=1
  else
    results+=("$suite: $line, ${secs} s")
  fi
done
wineserver -k 2>/dev/null || true

summary="$(printf '%s; ' "${results[@]}")"
summary="${summary%; }"
if [ "$failed" -ne 0 ]; then
  fail "$summary"
fi
echo "check_windows.sh: ok: ${dll_line#build_windows_dll.sh: }; under Wine $(wine --version 2>/dev/null): $summary"
