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
# solver (and core/ for its constants), the solver its executors. include/pbf_c_api.h (the
# public header) may be included from anywhere; tests/, tools/, samples/ and harness/ are
# outside the layers.
#
# Includes are not the only way around a door: a name the solver declares can reach the API
# through a header the world includes. So above the world (native/api/, native/interop/):
#   - no header they reach, directly or through others, is a solver header that declares a
#     name (world_cuda.h passes through backend_cuda.h, which declares none);
#   - none of the names native/solver/*.h declare at namespace scope (types, enum constants,
#     constants, free functions) is used; a use qualified by another scope (World::stage_name)
#     is that scope's name.
# What both sides of the world share (the live buffers) lives in common/.
# Usage: scripts/check_layers.sh [REPO_ROOT]
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

# ---- names the solver declares, used above the world ----------------------------------------
def strip_code(text):
    """The text without comments, string and character literals (line breaks kept)."""
    out = re.sub(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'',
                 lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S)
    return out

type_def = re.compile(r"^(?:template\s*<[^>]*>\s*)?(?:struct|class|union|enum(?:\s+class)?)\s+(\w+)\b(?!\s*;)")
constant = re.compile(r"^(?:inline\s+|static\s+)*constexpr\s+[\w:<>]+\s+(\w+)\s*[={]")
function = re.compile(r"^(?:template\s*<[^>]*>\s*)?(?:inline\s+|static\s+|PBF_HD\s+)*(?:[\w:<>]+[\s*&]+)+(\w+)\s*\(")
enumerator = re.compile(r"^\s+(k\w+)\b")
solver_dir = os.path.join(native, "solver")
declared = {}
for n in sorted(os.listdir(solver_dir)):
    if not n.endswith((".h", ".cuh")):
        continue
    with open(os.path.join(solver_dir, n), encoding="utf-8", errors="replace") as f:
        lines = strip_code(f.read()).splitlines()
    in_enum = False
    for line in lines:
        if in_enum:
            m = enumerator.match(line)
            if m:
                declared.setdefault(m.group(1), n)
            if "}" in line:
                in_enum = False
            continue
        for pattern in (type_def, constant, function):
            m = pattern.match(line)
            if m and m.group(1) not in ("operator",):
                declared.setdefault(m.group(1), n)
                break
        if re.match(r"^enum\b", line) and "{" in line and "}" not in line:
            in_enum = True

token = re.compile(r"(\.|->|(\w+)\s*::)?\s*\b([A-Za-z_]\w*)\b")
def solver_names_in(layer):
    uses = []
    top = os.path.join(native, layer)
    for dirpath, _, names in os.walk(top):
        for n in sorted(names):
            if not n.endswith((".h", ".hpp", ".c", ".cpp", ".cu", ".cuh")):
                continue
            path = os.path.join(dirpath, n)
            with open(path, encoding="utf-8", errors="replace") as f:
                text = strip_code(f.read())
            for lineno, line in enumerate(text.splitlines(), 1):
                if line.lstrip().startswith("#"):
                    continue
                for m in token.finditer(line):
                    qualifier, scope, name = m.group(1), m.group(2), m.group(3)
                    if qualifier and scope != "pbf":
                        continue  # a member, or a name of another scope
                    if name in declared:
                        uses.append(f"{os.path.relpath(path, root)}:{lineno}: {name} (solver/{declared[name]})")
    return uses

# ---- solver headers reached from above the world, through the headers in between ------------
naming = {os.path.join(solver_dir, n) for n in set(declared.values())}
def includes_of(path):
    out = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            m = include.match(line)
            if not m:
                continue
            target = os.path.normpath(os.path.join(os.path.dirname(path), m.group(1)))
            if not os.path.exists(target):
                target = os.path.normpath(os.path.join(native, m.group(1)))
            if target.startswith(native + os.sep) and os.path.exists(target):
                out.append(target)
    return out

def solver_headers_reached(path):
    """(solver header, include chain) for each naming solver header path reaches."""
    seen, found, todo = {path}, [], [(path, [])]
    while todo:
        here, chain = todo.pop()
        for target in includes_of(here):
            if target in seen:
                continue
            seen.add(target)
            step = chain + [os.path.relpath(target, native)]
            if target in naming:
                found.append((target, step))
            todo.append((target, step))
    return found

for layer in ("api", "interop"):
    for dirpath, _, names in os.walk(os.path.join(native, layer)):
        for n in sorted(names):
            if not n.endswith((".h", ".hpp", ".c", ".cpp", ".cu", ".cuh")):
                continue
            path = os.path.join(dirpath, n)
            for target, chain in solver_headers_reached(path):
                bad.append(f"{os.path.relpath(path, root)}: reaches {os.path.relpath(target, root)} "
                           f"({' -> '.join(chain)}), a solver header above the world")

if os.environ.get("CHECK_LAYERS_LIST_SOLVER_NAMES"):
    print(" ".join(sorted(declared)))
for layer in ("api", "interop"):
    for use in solver_names_in(layer):
        bad.append(f"{use}: a solver name above the world")

if bad:
    print("check_layers: includes against the layering (api > interop > world > solver > exec > core > common):")
    print("\n".join("  " + b for b in bad))
    sys.exit(1)
print(f"check_layers: {files} files under native/, every include points down through a door; "
      f"native/api/ and native/interop/ reach no solver header that declares a name and use none "
      f"of the {len(declared)} names native/solver/ declares")
PY
