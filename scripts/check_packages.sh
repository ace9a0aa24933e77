#!/usr/bin/env bash
# The C# packages' checks, for CI:
#
#   bash scripts/check_packages.sh [LIBDIR=build/lib]
#
#   1. scripts/check_unity_package.sh        the Unity package as Unity's importer reads it
#   2. pbf_packages.py unity-selftest        that check fails on broken copies of the package
#   3. scripts/check_nuget.sh LIBDIR         pack the NuGet package, validate it, consume it under Mono
#   4. pbf_packages.py native-selftest       the native checks (exports, no CUDA library linked, the
#                                            kernels carried, the same in both) fail on broken copies
#                                            of LIBDIR's libpbf.so and the Windows DLL; skipped, and
#                                            said so, where either lacks the kernels
#   5. scripts/check_csharp_mirror.py         the C# raw layer and the layout dump are what
#                                            scripts/gen_csharp_bindings.py makes of the header now,
#                                            every buffer kind has a BufferSource member, the
#                                            friendly layer reaches every desc field; self-tests
#   6. tools/check_unity_sample.sh           the package's UnityEngine scripts and its sample compile
#                                            (mcs against UnityEngine stubs; shaders with glslang);
#                                            skipped, and said so, without mcs or glslang
#
# LIBDIR holds a build of libpbf.so with CUDA for the NuGet package (the Unity package carries its own,
# committed plugins). The Windows DLL comes from build-mingw/lib/pbf.dll (built with
# scripts/build_windows_dll.sh when missing). PBF_UNITY_REQUIRE_WINDOWS=0 and
# PBF_NUGET_REQUIRE_WINDOWS=0 accept packages without it, with a warning.
# Ends with 'packages: N passed, N failed' (the checks of all six); exit 1 on any failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
libdir="${1:-build/lib}"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
rc=0
bash scripts/check_unity_package.sh 2>&1 | tee -a "$log"; [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
python3 scripts/pbf_packages.py unity-selftest bindings/csharp/unity 2>&1 | tee -a "$log"; [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
bash scripts/check_nuget.sh "$libdir" 2>&1 | tee -a "$log"; [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
source scripts/native_libs.sh
python3 scripts/pbf_packages.py native-selftest "$(find_libpbf "$libdir")" "${PBF_WINDOWS_DLL:-build-mingw/lib/pbf.dll}" 2>&1 | tee -a "$log"
native_rc="${PIPESTATUS[0]}"
closing=6
if [ "$native_rc" -eq 77 ]; then
  closing=$((closing - 1))
elif [ "$native_rc" -ne 0 ]; then
  rc=1
fi
python3 scripts/check_csharp_mirror.py 2>&1 | tee -a "$log"; [ "${PIPESTATUS[0]}" -eq 0 ] || rc=1
bash tools/check_unity_sample.sh 2>&1 | tee -a "$log"; sample_rc="${PIPESTATUS[0]}"
if [ "$sample_rc" -eq 77 ]; then
  closing=$((closing - 1))
  echo "unity sample: skipped (mcs or glslangValidator missing)"
elif [ "$sample_rc" -ne 0 ]; then
  rc=1
fi
# Sum the closing lines ('unity package:', 'unity check self-test:', 'nuget package:',
# 'native check self-test:', 'csharp mirror:', 'unity sample:'); a missing one counts as a failure.
titles='unity package|unity check self-test|nuget package|native check self-test|csharp mirror|unity sample'
read -r passed failed < <(sed -n -E "s/^($titles): ([0-9]+) passed, ([0-9]+) failed\$/\\2 \\3/p" "$log" \
  | awk -v want="$closing" '{p += $1; f += $2; n++} END {print p + 0, f + 0 + (n < want ? 1 : 0)}')
echo
grep -E "^($titles): " "$log"
echo "packages: $passed passed, $failed failed"
[ "$rc" -eq 0 ] && [ "$failed" -eq 0 ]
