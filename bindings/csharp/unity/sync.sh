#!/usr/bin/env bash
# Makes this folder a complete Unity package: copies the C# bindings (bindings/csharp/src, the
# single source of truth) into Runtime/Core/ and, when given, the native library into
# Plugins/x86_64/. Run it again after updating libpbf.
#
#   bindings/csharp/unity/sync.sh [LIBDIR]     LIBDIR holds libpbf.so.1 (e.g. build/lib)
#
# Then in Unity: Window > Package Manager > + > Add package from disk > this folder's package.json.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
rm -rf "$here/Runtime/Core"
mkdir -p "$here/Runtime/Core"
cp "$here"/../src/*.cs "$here/Runtime/Core/"
echo "copied $(ls "$here/Runtime/Core" | wc -l) C# files into Runtime/Core"
if [ $# -ge 1 ]; then
  lib="$1/libpbf.so.1"
  [ -e "$lib" ] || lib="$1/libpbf.so"
  if [ ! -e "$lib" ]; then echo "sync.sh: no libpbf.so in $1" >&2; exit 2; fi
  cp -L "$lib" "$here/Plugins/x86_64/libpbf.so"
  echo "copied $lib to Plugins/x86_64/libpbf.so"
fi
