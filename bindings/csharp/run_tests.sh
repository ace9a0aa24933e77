#!/usr/bin/env bash
# Builds the C# bindings and their NUnit tests with Mono's mcs and runs them against a built
# libpbf. Usage, from anywhere:
#
#   bindings/csharp/run_tests.sh [LIBDIR]     LIBDIR holds libpbf.so(.1); default <repo>/build/lib
#
# Needs cc, mcs, mono, nunit-console and the NUnit 2.6 framework
# (Debian/Ubuntu: apt-get install mono-mcs mono-runtime nunit-console libnunit-cil-dev).
# Output goes to bindings/csharp/build/ (or $PBF_CS_BUILD_DIR). Exits non-zero on any failure.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
libdir="${1:-$root/build/lib}"
if [ ! -d "$libdir" ]; then
  echo "run_tests.sh: library directory '$libdir' does not exist (build libpbf first)" >&2
  exit 2
fi
libdir="$(cd "$libdir" && pwd)"
if [ ! -e "$libdir/libpbf.so.1" ] && [ ! -e "$libdir/libpbf.so" ]; then
  echo "run_tests.sh: no libpbf.so or libpbf.so.1 in $libdir" >&2
  exit 2
fi
for tool in cc pkg-config mcs mono nunit-console; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "run_tests.sh: '$tool' not found (apt-get install pkg-config mono-mcs mono-runtime nunit-console libnunit-cil-dev)" >&2
    exit 2
  fi
done
if ! pkg-config --exists nunit 2>/dev/null; then
  echo "run_tests.sh: the NUnit framework (pkg-config nunit) is missing: apt-get install libnunit-cil-dev" >&2
  exit 2
fi

out="${PBF_CS_BUILD_DIR:-$here/build}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"

echo "== layout dump of include/pbf_c_api.h"
cc -std=c99 -Wall -Wextra -Werror -I "$root/include" "$here/tools/layout_dump.c" -o "$out/layout_dump"
"$out/layout_dump" > "$out/layout_expected.txt"
echo "   $(grep -c '^struct ' "$out/layout_expected.txt") structs, $(grep -c '^field ' "$out/layout_expected.txt") fields, $(grep -c '^enum ' "$out/layout_expected.txt") enum constants"

echo "== mcs: Pbf.dll (bindings)"
# C# 7.2 is mcs's newest: the bindings compile with it, hence with Unity's and .NET's compilers.
mcs -langversion:7.2 -target:library -warnaserror+ -nowarn:1591 -r:System.Numerics \
    -doc:"$out/Pbf.xml" -out:"$out/Pbf.dll" "$here"/unity/Runtime/Core/*.cs
cp "$here/Pbf.dll.config" "$out/Pbf.dll.config"

echo "== mcs: Pbf.Tests.dll"
mcs -langversion:7.2 -target:library -warnaserror+ -pkg:nunit -r:System.Numerics -r:"$out/Pbf.dll" \
    -out:"$out/Pbf.Tests.dll" "$here"/tests/*.cs

echo "== nunit-console (libpbf from $libdir)"
cd "$out"
rm -f TestResult.xml
set +e
LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
PBF_LAYOUT_FILE="$out/layout_expected.txt" \
  nunit-console -nologo -noshadow -labels -xml="$out/TestResult.xml" "$out/Pbf.Tests.dll"
rc=$?
set -e

if [ ! -f "$out/TestResult.xml" ]; then
  echo "run_tests.sh: nunit-console wrote no result (exit $rc)" >&2
  exit 1
fi
# The closing line: counts from the NUnit result file.
summary="$(sed -n 's/.*<test-results [^>]*total="\([0-9]*\)" errors="\([0-9]*\)" failures="\([0-9]*\)" not-run="\([0-9]*\)".*/\1 \2 \3 \4/p' "$out/TestResult.xml")"
read -r total errors failures notrun <<< "${summary:-0 0 0 0}"
failed=$((errors + failures))
passed=$((total - failed - notrun))
echo
echo "csharp: $passed passed, $failed failed, $notrun skipped"
if [ "$rc" -ne 0 ] || [ "$failed" -ne 0 ] || [ "$total" -eq 0 ]; then
  exit 1
fi
