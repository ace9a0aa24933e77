#!/usr/bin/env bash
# Builds the LibPbf NuGet package from bindings/csharp/nuget/Pbf.nuspec:
#
#   bash scripts/pack_nuget.sh [LIBDIR=build/lib] [OUTDIR=bindings/csharp/build/nuget]
#
#   lib/netstandard2.1/Pbf.dll (+ Pbf.xml, Pbf.dll.config)  the bindings, compiled with Mono's mcs
#   runtimes/linux-x64/native/libpbf.so                     from LIBDIR (a build with CUDA: scripts/build.sh)
#   runtimes/win-x64/native/pbf.dll                         from $PBF_WINDOWS_DLL (default
#                                                           build-mingw/lib/pbf.dll)
#
# When the Windows DLL is missing and scripts/build_windows_dll.sh exists, it is built with that
# script (PBF_NUGET_BUILD_WINDOWS=0 skips this); when it still is missing, the package is packed
# for Linux only with a WARNING, and the package check then fails unless
# PBF_NUGET_REQUIRE_WINDOWS=0.
#
# Pbf.dll: Debian ships no netstandard reference assembly, so mcs compiles the bindings against
# Mono's 4.x class library (mscorlib, System, System.Core, System.Numerics). The sources use only
# the netstandard2.1 API (they are also built as netstandard2.1 by Pbf.csproj with the .NET SDK);
# the assembly loads on Mono and Unity. For .NET (Core) and Godot, build the package's assembly
# from Pbf.csproj (`dotnet pack`), which references netstandard itself. See
# bindings/csharp/README.md.
#
# The .nupkg is assembled by scripts/pbf_packages.py (the zip layout 'nuget pack' writes):
# Debian's nuget is 2.8, whose nuspec schema predates <license type="expression"> (NuGet 4.9)
# and refuses it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
libdir="${1:-build/lib}"
out="${2:-bindings/csharp/build/nuget}"
dll="${PBF_WINDOWS_DLL:-build-mingw/lib/pbf.dll}"

need=()
command -v mcs >/dev/null 2>&1 || need+=(mono-mcs)
command -v mono >/dev/null 2>&1 || need+=(mono-runtime)
[ -e /usr/lib/mono/4.5/System.Numerics.dll ] || need+=(libmono-system-numerics4.0-cil)
if [ "${#need[@]}" -gt 0 ]; then
  echo "pack_nuget.sh: installing ${need[*]}"
  sudo_=""; [ "$(id -u)" -eq 0 ] || sudo_=sudo
  DEBIAN_FRONTEND=noninteractive $sudo_ apt-get install -y -qq "${need[@]}" >/dev/null
fi

# The library the build links as libpbf.so (a build folder can also hold an older major's file).
source scripts/native_libs.sh
so="$(find_libpbf "$libdir")"
if [ -z "$so" ]; then
  echo "pack_nuget.sh: no libpbf.so in '$libdir' (build libpbf first: scripts/build.sh)" >&2
  exit 2
fi

stage="$out/stage"
rm -rf "$stage"
mkdir -p "$stage/lib/netstandard2.1" "$stage/runtimes/linux-x64/native" "$stage/runtimes/win-x64/native"

echo "== mcs: lib/netstandard2.1/Pbf.dll"
mcs -langversion:7.2 -target:library -optimize+ -warnaserror+ -nowarn:1591 -r:System.Numerics \
    -doc:"$stage/lib/netstandard2.1/Pbf.xml" -out:"$stage/lib/netstandard2.1/Pbf.dll" \
    bindings/csharp/unity/Runtime/Core/*.cs
cp bindings/csharp/Pbf.dll.config "$stage/lib/netstandard2.1/"

echo "== runtimes/linux-x64/native/libpbf.so <- $so"
copy_stripped "$so" "$stage/runtimes/linux-x64/native/libpbf.so"

if [ ! -f "$dll" ] && [ "${PBF_NUGET_BUILD_WINDOWS:-1}" != "0" ] && [ -f scripts/build_windows_dll.sh ] \
   && [ "$dll" = "build-mingw/lib/pbf.dll" ]; then
  echo "== $dll missing: building it with scripts/build_windows_dll.sh"
  bash scripts/build_windows_dll.sh build-mingw
fi
optional=()
if [ -f "$dll" ]; then
  echo "== runtimes/win-x64/native/pbf.dll <- $dll"
  copy_stripped "$dll" "$stage/runtimes/win-x64/native/pbf.dll"
else
  echo "################################################################################" >&2
  echo "pack_nuget.sh: WARNING: no Windows DLL ($dll)$( [ -f scripts/build_windows_dll.sh ] || echo ', and no scripts/build_windows_dll.sh to build it'):" >&2
  echo "  the package is LINUX-ONLY (no runtimes/win-x64/native/pbf.dll)" >&2
  echo "################################################################################" >&2
  optional=(--optional runtimes/win-x64/native/pbf.dll)
fi

echo "== assemble"
rm -f "$out"/*.nupkg
nupkg="$(python3 scripts/pbf_packages.py nupkg bindings/csharp/nuget/Pbf.nuspec "$stage" "$out" "${optional[@]}")"
echo "$nupkg"
unzip -l "$nupkg" | sed -n '4,$p' | grep -v -e '^-' -e 'files$' | awk '{print "   " $4 "  (" $1 " bytes)"}'
