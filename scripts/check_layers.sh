#!/usr/bin/env bash
# Fails when an #include in native/ points from a lower layer to a higher one, or goes around a
# layer's door, printing each offending line. Layers, top to bottom:
#
#   api      native/api        the C ABI: validates, translates, calls World and Interop
#   interop  native/interop    zero-copy rendering, beside the world (reaches it through World)
#   world    native/world      worlds, emitters, colliders; the only door to the solver
#   solver   native/solver     the step, written once (Solver<Exec>), and the Backend door
#   exec     native/exec       the executors: CpuExec (OpenMP), CudaExec (CUDA)
#   core     native/core       per-particle operations, SPH kernels, grid, collisions, constants
#   common   native/common     Status, handle tables, the transfer counter
#
# A file may include its own layer, common/, and the layers named in `reach` below: the API
# reaches the world and interop only (never the solver or an executor), the world reaches the
# solver (and core/ for its constants), the solver its executors. include/pbf_c_api.h (the public header) may be included from anywhere; tests/, tools/ and
# samples/ are outside the layers. Usage: scripts/check_layers.sh [REPO_ROOT]
set -euo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
if ! command -v python3 >/dev/null; then
  echo "check_layers: python3 not found: skipped"
  exit 77  # ctest: skipped
fi
exec python3 - "$root" <<'PY'
import os, re, sys

root = sys.argv[1]
native = os.path.join(root, "native")
rank = {"common": 0, "core": 1, "exec": 2, "solver": 3, "world": 4, "interop": 5, "api": 6}

reach = {"api": {"interop", "world"}, "interop": {"world"}, "world": {"solver", "core"},
         "solver": {"exec", "core"}, "exec": {"core"}, "core": set(), "common": set()}
include = re.compile(r'^\s*#\s*include\s*"([^"]+)"')

def layer_of(path):
    rel = os.path.relpath(path, native).split(os.sep)
    return rel[0] if len(rel) > 1 and rel[0] in rank else None

bad, files = [], 0
for dirpath, _, names in os.walk(native):
    for n in sorted(names):
        if not n.endswith((".h", ".hpp", ".c", ".cpp", ".cu", ".cuh")):
            continue
        path = os.path.join(dirpath, n)
        here = layer_of(path)
        if here is None:
            bad.append(f"{os.path.relpath(path, root)}: not in a layer (native/<layer>/...)")
            continue
        files += 1
        with open(path, encoding="utf-8", errors="replace") as f:
            for lineno, line in enumerate(f, 1):
                m = include.match(line)
                if not m:
                    continue
                target = os.path.normpath(os.path.join(dirpath, m.group(1)))
                if not os.path.exists(target):
                    # Not relative to the file: the public header or a path from native/.
                    if os.path.exists(os.path.join(root, "include", m.group(1))):
                        continue
                    target = os.path.normpath(os.path.join(native, m.group(1)))
                there = layer_of(target) if target.startswith(native + os.sep) else None
                if there is None:
                    bad.append(f"{os.path.relpath(path, root)}:{lineno}: includes {m.group(1)}, outside the layers")
                elif there != here and there != "common" and there not in reach[here]:
                    why = "points up" if rank[there] > rank[here] else "goes around a layer's door"
                    bad.append(f"{os.path.relpath(path, root)}:{lineno}: {line.strip()}  "
                               f"({here} -> {there}: {why})")

if bad:
    print("check_layers: includes against the layering (api > interop > world > solver > exec > core > common):")
    print("\n".join("  " + b for b in bad))
    sys.exit(1)
print(f"check_layers: {files} files under native/, every include points down through a door")
PY
