#!/usr/bin/env bash
# Checks the tree, builds libpbf (scripts/build.sh, into build/) and runs every test this machine
# can run:
#   0. scripts/check_history.sh and scripts/check_format.sh before the build (code, README and
#      docs cite no issue numbers or periods of work; the C/C++ sources are as clang-format
#      formats them) and scripts/check_links.py after it (every relative Markdown link resolves;
#      it needs the python3 the build's package check installs); seconds each;
#   1. ctest: the C/C++ suites (unit, CPU scenes, C ABI), the driver tests against the stub CUDA
#      driver (label backend) and the version check (label packaging); the [gpu] suite shows as
#      Skipped where no CUDA device can be used;
#   2. bindings/csharp/run_tests.sh: the C# bindings' NUnit tests against build/lib;
#   3. scripts/check_install.sh: build/ installed into a temporary prefix and used by a small C
#      program through find_package(pbf) and through pkg-config;
#   4. scripts/check_windows.sh: the MinGW-w64 pbf.dll (build-mingw/, with build/'s CUDA kernels)
#      and the C API and driver tests under Wine; skipped, and said so, where the MinGW compiler
#      or Wine cannot be installed;
#   5. scripts/check_packages.sh: the Unity package (as Unity's importer reads it, its committed
#      plugins against the header) and the NuGet package (packed, validated, consumed under Mono
#      with build/lib).
# All run even if one fails; exits non-zero if the build or any suite fails.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
build="build"

echo "== tree (scripts/check_history.sh, scripts/check_format.sh, then scripts/check_links.py after the build)"
bash scripts/check_history.sh
history_rc=$?
bash scripts/check_format.sh
format_rc=$?

if ! bash scripts/build.sh "$build"; then
  echo "run_tests.sh: the build failed" >&2
  exit 1
fi
python3 scripts/check_links.py
links_rc=$?

# suite KEY TITLE CMD...: runs CMD, its output shown and kept in $build/run_tests.KEY.log; sets
# KEY_rc (its exit status) and KEY_secs (its wall time).
suite() {
  local key=$1 title=$2 start
  shift 2
  echo
  echo "== $title"
  start=$(date +%s)
  "$@" 2>&1 | tee "$build/run_tests.$key.log"
  printf -v "${key}_rc" '%s' "${PIPESTATUS[0]}"
  printf -v "${key}_secs" '%s' "$(( $(date +%s) - start ))"
}

# summary_line LABEL KEY PREFIX [timed]: the last line of KEY's log that starts with PREFIX,
# without it, with KEY's wall time when timed, and its exit status.
summary_line() {
  local label=$1 key=$2 prefix=$3 timed=${4:-} line rc_var="${2}_rc" secs_var="${2}_secs" secs=""
  line="$(grep -E "^$prefix" "$build/run_tests.$key.log" | tail -n 1)"
  [ -n "$timed" ] && secs=" (${!secs_var} s)"
  if [ -n "$line" ]; then
    echo "$label ${line#"$prefix"}$secs [exit ${!rc_var}]"
  else
    echo "$label no summary line (exit ${!rc_var})"
  fi
}

suite ctest "ctest (C/C++ tests; [gpu] tests are Skipped without a CUDA device)" \
  ctest --test-dir "$build" --output-on-failure --no-tests=error -j2
suite csharp "C# bindings (bindings/csharp/run_tests.sh $build/lib)" \
  bash bindings/csharp/run_tests.sh "$build/lib"
suite install "install and consume (scripts/check_install.sh $build)" \
  bash scripts/check_install.sh "$build"
# The Windows DLL embeds the kernels this build's nvcc made (they are the same for every OS).
windows_fatbin=""
[ -f "$build/pbf_kernels.fatbin" ] && windows_fatbin="$build/pbf_kernels.fatbin"
suite windows "Windows (scripts/check_windows.sh: MinGW-w64 pbf.dll, C API and driver tests under Wine)" \
  env PBF_CUDA_FATBIN="$windows_fatbin" bash scripts/check_windows.sh build-mingw
suite packages "packages (scripts/check_packages.sh $build/lib: Unity package, NuGet package)" \
  bash scripts/check_packages.sh "$build/lib"

ctest_summary="$(grep -E 'tests passed, [0-9]+ tests? failed out of' "$build/run_tests.ctest.log" | tail -n 1)"
ctest_skipped="$(grep -c '(Skipped)$' "$build/run_tests.ctest.log")"

echo
echo "== summary"
echo "tree:   history [exit $history_rc], format [exit $format_rc], links [exit $links_rc]"
if [ -n "$ctest_summary" ]; then
  echo "ctest:  $ctest_summary ($ctest_skipped skipped) [exit $ctest_rc]"
else
  echo "ctest:  no summary line (exit $ctest_rc)"
fi
summary_line csharp: csharp "csharp: "
summary_line install: install "check_install.sh: " timed
summary_line windows: windows "check_windows.sh: " timed
summary_line packages: packages "packages: " timed

if [ "$history_rc" -ne 0 ] || [ "$format_rc" -ne 0 ] || [ "$links_rc" -ne 0 ] || [ "$ctest_rc" -ne 0 ] || [ "$csharp_rc" -ne 0 ] || [ "$install_rc" -ne 0 ] || [ "$windows_rc" -ne 0 ] ||
   [ "$packages_rc" -ne 0 ]; then
  echo "run_tests.sh: FAILED"
  exit 1
fi
echo "run_tests.sh: all passed"
