#!/usr/bin/env bash
# Packs the LibPbf NuGet package and consumes it under Mono:
#
#   bash scripts/check_nuget.sh [LIBDIR=build/lib]
#
# 1. scripts/pack_nuget.sh LIBDIR -> bindings/csharp/build/nuget/LibPbf.<version>.nupkg
# 2. validate it: licence expression, version == include/pbf_c_api.h, OPC parts, the assembly,
#    and for each native library its format, CPU and exports (== the header's pbf_* functions);
#    pbf.dll must need only Windows' own DLLs
# 3. restore it with 'nuget install' (Debian's nuget 2.8, from a local folder source) into a
#    temporary folder, compile bindings/csharp/nuget/consumer/Consumer.cs with mcs against the
#    packaged Pbf.dll (copied beside the program, as a build copies a reference), and run it under
#    Mono with LD_LIBRARY_PATH=<package>/runtimes/linux-x64/native: Mono has no notion of NuGet's
#    runtimes/ folders, so the package's native folder is put on the loader's path (a .NET (Core)
#    app resolves runtimes/<rid>/native by itself). The program creates a world, steps it, checks
#    that the libpbf it mapped is the package's, and prints OK.
#
# A package without runtimes/win-x64/native/pbf.dll fails the check unless
# PBF_NUGET_REQUIRE_WINDOWS=0 (then it says 'Linux-only'). Installs mono-mcs, mono-runtime and
# nuget with apt-get when missing. Ends with 'nuget package: N passed, N failed'.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
libdir="${1:-build/lib}"
out="bindings/csharp/build/nuget"

need=()
command -v mcs >/dev/null 2>&1 || need+=(mono-mcs)
command -v mono >/dev/null 2>&1 || need+=(mono-runtime)
command -v nuget >/dev/null 2>&1 || need+=(nuget)
command -v unzip >/dev/null 2>&1 || need+=(unzip)
if [ "${#need[@]}" -gt 0 ]; then
  echo "check_nuget.sh: installing ${need[*]}"
  sudo_=""; [ "$(id -u)" -eq 0 ] || sudo_=sudo
  DEBIAN_FRONTEND=noninteractive $sudo_ apt-get install -y -qq "${need[@]}" >/dev/null
fi

bash scripts/pack_nuget.sh "$libdir" "$out"
version="$(python3 scripts/pbf_packages.py header-version)"
nupkg="$(ls "$out"/LibPbf.*.nupkg | head -n 1)"

set +e
python3 scripts/pbf_packages.py nupkg-check "$nupkg" | tee "$out/check.txt"
set -e
passed="$(sed -n 's/^nuget package contents: \([0-9]*\) passed, \([0-9]*\) failed$/\1/p' "$out/check.txt")"
failed="$(sed -n 's/^nuget package contents: \([0-9]*\) passed, \([0-9]*\) failed$/\2/p' "$out/check.txt")"
if unzip -l "$nupkg" runtimes/win-x64/native/pbf.dll >/dev/null 2>&1; then
  platforms="linux-x64 and win-x64"
else
  platforms="linux-x64 only: WARNING, no runtimes/win-x64/native/pbf.dll"
fi

echo "== consumer: nuget install from a local source, mcs, mono"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
pkgver="$(basename "$nupkg" .nupkg)"; pkgver="${pkgver#LibPbf.}"
nuget install LibPbf -Version "$pkgver" -Source "$root/$out" -OutputDirectory "$tmp/packages" \
      -NonInteractive -NoCache 2>&1 | sed 's/^/   /'
pkg="$tmp/packages/LibPbf.$pkgver"
mkdir -p "$tmp/app"
cp "$pkg/lib/netstandard2.1/Pbf.dll" "$pkg/lib/netstandard2.1/Pbf.dll.config" "$tmp/app/"
consumer_ok=0
if mcs -langversion:7.2 -warnaserror+ -r:System.Numerics -r:"$tmp/app/Pbf.dll" -out:"$tmp/app/Consumer.exe" \
       bindings/csharp/nuget/consumer/Consumer.cs; then
  native="$pkg/runtimes/linux-x64/native"
  if LD_LIBRARY_PATH="$native" mono "$tmp/app/Consumer.exe" "$native" 2>&1 | sed 's/^/   /' | tee "$tmp/run.txt" \
     && grep -qx '   OK' "$tmp/run.txt"; then
    consumer_ok=1
  fi
fi
if [ "$consumer_ok" = 1 ]; then
  echo "  ok    consumer under Mono: world created and stepped with the package's libpbf"
  passed=$((passed + 1))
else
  echo "  FAIL  consumer under Mono"
  failed=$((failed + 1))
fi
echo "nuget package: LibPbf $pkgver, $platforms"
echo "nuget package: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
