#!/usr/bin/env bash
# Builds the C# bindings and the samples with Mono's mcs, then runs one:
#
#   samples/csharp/run.sh [particles=32768] [steps=300] [iterations=4]     the dam break
#   samples/csharp/run.sh --floating-box [steps=300]                        two-way coupling
#
# PBF_LIB_DIR: the directory holding libpbf.so(.1) (default <repo>/build/lib).
# PBF_BACKEND, PBF_LDC, PBF_SUBSTEPS: as for samples/dam_break.c.
# Needs mcs and mono (Debian/Ubuntu: apt-get install mono-mcs mono-runtime).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
libdir="${PBF_LIB_DIR:-$root/build/lib}"
if [ ! -e "$libdir/libpbf.so.1" ] && [ ! -e "$libdir/libpbf.so" ]; then
  echo "run.sh: no libpbf.so in '$libdir' (build libpbf, or set PBF_LIB_DIR)" >&2
  exit 2
fi
libdir="$(cd "$libdir" && pwd)"
out="$here/build"
mkdir -p "$out"

mcs -langversion:7.2 -target:library -nowarn:1591 -r:System.Numerics -out:"$out/Pbf.dll" \
    "$root"/bindings/csharp/unity/Runtime/Core/*.cs
cp "$root/bindings/csharp/Pbf.dll.config" "$out/Pbf.dll.config"
sample=DamBreak
if [ "${1:-}" = "--floating-box" ]; then sample=FloatingBox; shift; fi
mcs -langversion:7.2 -r:System.Numerics -r:"$out/Pbf.dll" -out:"$out/$sample.exe" "$here/$sample.cs"

LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" exec mono "$out/$sample.exe" "$@"
