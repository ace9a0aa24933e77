#!/usr/bin/env bash
# The Windows build, checked on Linux: cross-builds pbf.dll with both backends with MinGW-w64
# (scripts/build_windows_dll.sh: only pbf_* exported, only Windows' own DLLs imported, the CUDA
# kernels embedded), builds the Catch2 suites that run on the CPU backend for Windows and the
# driver tests, and runs them under Wine (which has no NVIDIA driver):
#
#   bash scripts/check_windows.sh [BUILD_DIR=build-mingw]
#
#   pbf_api_tests          the C ABI: versions, struct layout (tests/header_c99.c), validation,
#                          handles, capacity, mapping, logging, thread-local errors
#   pbf_reliability_tests  fuzz-finding regressions, out of memory, capacity, threads
#   pbf_unit_tests         white-box: SPH kernels, LDC, neighbour masks, colliders and the CPU
#                          scenes (resting tank, dam break, nozzles, drains), on the static core
#   pbf_backend_tests      how the DLL finds the GPU: one Wine process per case of
#                          tests/stub_driver/cases.txt, as ctest runs them on Linux: no nvcuda.dll
#                          in System32 (the stub planted beside the program must not be taken),
#                          a driver path with no file, and the stub nvcuda.dll playing each
#                          machine without a usable GPU
#
# PBF_CUDA_FATBIN (a Linux build's pbf_kernels.fatbin) spares the nvcc build of the kernels
# (scripts/run_tests.sh passes build/'s).
#
# Test cases that cannot work under Windows would be excluded by Catch2 tag here (none are).
# Wine runs headless in a temporary prefix (about 0.7 GB, made in some seconds and removed at
# the end; PBF_WINEPREFIX=DIR keeps one instead), with WINEDEBUG=-all and Wine's Mono and Gecko
# installers switched off.
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
driver_suite=pbf_backend_tests
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
if ! bash scripts/build_windows_dll.sh "$build" "${suites[@]}" "$driver_suite" >"$build_log" 2>&1; then
  grep -E -B2 -A6 'error|Error|build_windows_dll.sh:' "$build_log" | head -60
  fail "the MinGW build ($build_log)"
fi
dll_line="$(grep -E '^build_windows_dll.sh: ' "$build_log" | tail -n 1)"
echo "$dll_line"

case "$build" in /*) build_abs="$build" ;; *) build_abs="$root/$build" ;; esac
if [ -n "${PBF_WINEPREFIX:-}" ]; then
  mkdir -p "$PBF_WINEPREFIX"
  export WINEPREFIX="$(cd "$PBF_WINEPREFIX" && pwd)"
else
  export WINEPREFIX="$(mktemp -d "${TMPDIR:-/tmp}/pbf-wine.XXXXXX")"
  trap 'wineserver -k 2>/dev/null; rm -rf "$WINEPREFIX"' EXIT
fi
export WINEDEBUG=-all
export WINEDLLOVERRIDES="mscoree,mshtml="  # no Mono/Gecko install dialogs
export WINEPATH="Z:$(tr '/' '\\' <<<"$build_abs/lib")"  # where pbf.dll is
unset DISPLAY
if [ ! -f "$WINEPREFIX/system.reg" ]; then
  echo "== creating the Wine prefix $WINEPREFIX"
  wineboot --init >"$build/check_windows.wineboot.log" 2>&1
  wineserver -w 2>/dev/null || true
fi

# A suite that does not exit within this many seconds (they take under a minute) has hung: it is
# stopped and reported, and its cases are run one process each to name the one that hangs,
# instead of the hang holding the whole check until an outer time limit.
suite_limit="${PBF_WINE_SUITE_TIMEOUT:-600}"
case_limit=$(( suite_limit / 4 ))
hung() {  # EXE LOG SUMMARY: what is known of a suite that did not exit
  local exe=$1 log=$2 summary=$3 name rc
  echo "HUNG: $exe did not exit within $suite_limit s"
  if [ -n "$summary" ]; then
    echo "  its cases all finished ($summary): it hung on the way out of the process"
  fi
  echo "  each case in its own process (at most $case_limit s each):"
  tr -d '\r' < <(wine "$exe" --list-test-names-only 2>/dev/null) | while IFS= read -r name; do
    [ -n "$name" ] || continue
    # A name as a Catch2 test spec: its commas and brackets escaped.
    timeout -k 15 "$case_limit" wine "$exe" "$(sed 's/[],[\\]/\\&/g' <<<"$name")" >"$log.case" 2>&1
    rc=$?
    case "$rc" in
      0) echo "    ok    $name" ;;
      124 | 137) echo "    HUNG  $name" ;;
      *) echo "    FAIL  $name (exit $rc)" ;;
    esac
  done
}

declare -a results=()
failed=0
for suite in "${suites[@]}"; do
  exe="$build/tests/$suite.exe"
  echo
  echo "== wine $exe ${spec[$suite]}"
  log="$build/check_windows.$suite.log"
  start=$(date +%s)
  # shellcheck disable=SC2086  # the spec is one word or none
  timeout -k 15 "$suite_limit" wine "$exe" ${spec[$suite]} >"$log" 2>&1
  rc=$?
  secs=$(( $(date +%s) - start ))
  tr -d '\r' <"$log" | tail -n 3
  line="$(tr -d '\r' <"$log" | grep -E '^(All tests passed|test cases:)' | tail -n 1)"
  if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
    hung "$exe" "$log" "$line"
    results+=("$suite FAILED: no exit within $suite_limit s (${line:-no Catch2 summary}; $log)")
    failed=1
  elif [ "$rc" -ne 0 ] || [ -z "$line" ]; then
    tr -d '\r' <"$log" | grep -E -B3 -A12 'FAILED|failed' | head -60
    results+=("$suite FAILED: ${line:-no Catch2 summary} (exit $rc, $log)")
    failed=1
  else
    results+=("$suite: $line, ${secs} s")
  fi
done

# The driver cases: each its own process (the driver is opened once per process).
winpath() { echo "Z:$(tr '/' '\\' <<<"$1")"; }
stubs="$build_abs/tests/stub_driver"
echo
echo "== wine $build/tests/$driver_suite.exe, one process per case of tests/stub_driver/cases.txt"
log="$build/check_windows.$driver_suite.log"
: >"$log"
start=$(date +%s)
passed=0
driver_failed=()
while read -r name driver mode; do
  case "$name" in "" | "#"*) continue ;; esac
  case "$driver" in
    system) path="" ;;
    missing) path="$(winpath "$stubs/missing/nvcuda.dll")" ;;
    *) path="$(winpath "$stubs/$driver/nvcuda.dll")" ;;
  esac
  [ "$mode" = "-" ] && mode=""
  vars=()
  [ -n "$path" ] && vars+=("PBF_CUDA_DRIVER=$path")
  [ -n "$mode" ] && vars+=("PBF_STUB_CUDA=$mode")
  echo "-- $name: PBF_CUDA_DRIVER=${path:-(unset)} PBF_STUB_CUDA=${mode:-(unset)}" >>"$log"
  if env -u PBF_CUDA_DRIVER -u PBF_STUB_CUDA "${vars[@]}" \
       wine "$build/tests/$driver_suite.exe" "[driver-$name]" --warn NoTests >>"$log" 2>&1; then
    passed=$((passed + 1))
  else
    driver_failed+=("$name")
  fi
done <tests/stub_driver/cases.txt
secs=$(( $(date +%s) - start ))
if [ "${#driver_failed[@]}" -gt 0 ]; then
  tr -d '\r' <"$log" | grep -E -B3 -A12 'FAILED|failed|^-- ' | head -80
  results+=("$driver_suite FAILED: cases ${driver_failed[*]} ($log)")
  failed=1
else
  echo "all $passed cases passed"
  results+=("$driver_suite: $passed driver cases passed, ${secs} s")
fi
wineserver -k 2>/dev/null || true

summary="$(printf '%s; ' "${results[@]}")"
summary="${summary%; }"
if [ "$failed" -ne 0 ]; then
  fail "$summary"
fi
echo "check_windows.sh: ok: ${dll_line#build_windows_dll.sh: }; under Wine $(wine --version 2>/dev/null): $summary"
