#!/usr/bin/env bash
# Builds libpbf (scripts/build.sh, into build/) and runs every test this machine can run:
#   1. ctest: the C/C++ suites (unit, CPU scenes, C ABI) and the version check (label
#      packaging); the [gpu] suite shows as Skipped where no CUDA device can be used;
#   2. bindings/csharp/run_tests.sh: the C# bindings' NUnit tests against build/lib;
#   3. scripts/check_install.sh: build/ installed into a temporary prefix and used by a small C
#      program through find_package(pbf) and through pkg-config;
#   4. scripts/check_windows.sh: the MinGW-w64 pbf.dll (build-mingw/) and the C API tests under
#      Wine; skipped, and said so, where the MinGW compiler or Wine cannot be installed;
#   5. scripts/check_packages.sh: the Unity package (as Unity's importer reads it, its committed
#      plugins against the header) and the NuGet package (packed, validated, consumed under Mono
#      with build/lib).
# All run even if one fails; exits non-zero if the build or any suite fails.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
build="build"

if ! bash scripts/build.sh "$build"; then
  echo "run_tests.sh: the build failed" >&2
  exit 1
fi

echo
echo "== ctest (C/C++ tests; [gpu] tests are Skipped without a CUDA device)"
ctest_log="$build/run_tests.ctest.log"
ctest --test-dir "$build" --output-on-failure --no-tests=error -j2 2>&1 | tee "$ctest_log"
ctest_rc=${PIPESTATUS[0]}

echo
echo "== C# bindings (bindings/csharp/run_tests.sh $build/lib)"
cs_log="$build/run_tests.csharp.log"
bash bindings/csharp/run_tests.sh "$build/lib" 2>&1 | tee "$cs_log"
cs_rc=${PIPESTATUS[0]}

echo
echo "== install and consume (scripts/check_install.sh $build)"
install_log="$build/run_tests.install.log"
start=$(date +%s)
bash scripts/check_install.sh "$build" 2>&1 | tee "$install_log"
install_rc=${PIPESTATUS[0]}
install_secs=$(( $(date +%s) - start ))

echo
echo "== Windows (scripts/check_windows.sh: MinGW-w64 pbf.dll, C API tests under Wine)"
windows_log="$build/run_tests.windows.log"
start=$(date +%s)
bash scripts/check_windows.sh build-mingw 2>&1 | tee "$windows_log"
windows_rc=${PIPESTATUS[0]}
windows_secs=$(( $(date +%s) - start ))

echo
echo "== packages (scripts/check_packages.sh $build/lib: Unity package, NuGet package)"
packages_log="$build/run_tests.packages.log"
start=$(date +%s)
bash scripts/check_packages.sh "$build/lib" 2>&1 | tee "$packages_log"
packages_rc=${PIPESTATUS[0]}
packages_secs=$(( $(date +%s) - start ))

ctest_summary="$(grep -E 'tests passed, [0-9]+ tests? failed out of' "$ctest_log" | tail -n 1)"
ctest_skipped="$(grep -c '(Skipped)$' "$ctest_log")"
cs_summary="$(grep -E '^csharp: ' "$cs_log" | tail -n 1)"
install_summary="$(grep -E '^check_install.sh: ' "$install_log" | tail -n 1)"
windows_summary="$(grep -E '^check_windows.sh: ' "$windows_log" | tail -n 1)"
packages_summary="$(grep -E '^packages: ' "$packages_log" | tail -n 1)"

echo
echo "== summary"
if [ -n "$ctest_summary" ]; then
  echo "ctest:  $ctest_summary ($ctest_skipped skipped) [exit $ctest_rc]"
else
  echo "ctest:  no summary line (exit $ctest_rc)"
fi
if [ -n "$cs_summary" ]; then
  echo "csharp: ${cs_summary#csharp: } [exit $cs_rc]"
else
  echo "csharp: no summary line (exit $cs_rc)"
fi
if [ -n "$install_summary" ]; then
  echo "install: ${install_summary#check_install.sh: } (${install_secs} s) [exit $install_rc]"
else
  echo "install: no summary line (exit $install_rc)"
fi
if [ -n "$windows_summary" ]; then
  echo "windows: ${windows_summary#check_windows.sh: } (${windows_secs} s) [exit $windows_rc]"
else
  echo "windows: no summary line (exit $windows_rc)"
fi
if [ -n "$packages_summary" ]; then
  echo "packages: ${packages_summary#packages: } (${packages_secs} s) [exit $packages_rc]"
else
  echo "packages: no summary line (exit $packages_rc)"
fi

if [ "$ctest_rc" -ne 0 ] || [ "$cs_rc" -ne 0 ] || [ "$install_rc" -ne 0 ] || [ "$windows_rc" -ne 0 ] ||
   [ "$packages_rc" -ne 0 ]; then
  echo "run_tests.sh: FAILED"
  exit 1
fi
echo "run_tests.sh: all passed"
