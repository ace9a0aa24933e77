#!/usr/bin/env bash
# Validates the Unity package bindings/csharp/unity (or DIR) the way Unity's importer reads an
# immutable package installed from a git URL:
#
#   bash scripts/check_unity_package.sh [DIR]
#
# - every file and folder has a .meta (except the names Unity skips: starting with '.', ending in
#   '~', 'cvs', '*.tmp'), no .meta is orphaned, every GUID is 32 lower-case hex digits and unique,
#   folders are folderAssets, each importer fits its file type; the sample folders under Samples~
#   likewise (they are copied into Assets/ with their .meta files), and the GUIDs their scene and
#   material refer to exist;
# - package.json: valid, name/version/displayName/description/unity/license/author, absolute URLs
#   only, sample paths exist, version == include/pbf_c_api.h's; CHANGELOG.md, LICENSE.md (== the
#   repository's LICENSE), Documentation~/*.md, an .asmdef;
# - Plugins/x86_64/libpbf.so and pbf.dll: .meta enables each for its editor OS and standalone
#   target with CPU x86_64 and nothing else; ELF64/PE32+ x86_64; exports exactly the header's
#   pbf_* functions; pbf.dll needs only Windows' own DLLs; libpbf.so loads and reports the header's
#   version; both match the sha256 in Plugins/x86_64/README.md's provenance table.
#
# Environment: PBF_UNITY_REQUIRE_WINDOWS=0 turns a missing pbf.dll into a warning;
# PBF_UNITY_STRICT=1 fails (instead of warning) when native/, include/ or CMake changed after the
# plugins were built. Ends with 'unity package: N passed, N failed'; exit 1 on any failure.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
command -v python3 >/dev/null 2>&1 || { echo "check_unity_package.sh: python3 not found" >&2; exit 2; }
exec python3 "$root/scripts/pbf_packages.py" unity-check "${1:-$root/bindings/csharp/unity}"
