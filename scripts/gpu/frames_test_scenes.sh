#!/usr/bin/env bash
# The frames of the tests' scenes (docs/render/<scene>/), in one call on the GPU machine from the
# repository root: the tests' scenes drawn by pbf_render_gl as a screen-space surface, coloured
# by material, with the colliders at their pose, 1280x720, through the zero-copy path:
#   materials: two_fluids (500 and 1000 kg/m³ stratifying, 4 s), droplet (a cube relaxing to a
#             sphere in zero gravity, 3 s), hanging_drops (with and without adhesion, 2 s);
#   colliders: container (a closed box mesh moved 20 radii and turned 30° per frame, the leak
#             test's motion, 10 s), floating_boxes (500 and 2000 kg/m³ boxes on a pool, the engine
#             integrating them from the force and torque read back, 4 s).
# The scenes are small (the tests' sizes, at most ~5k particles): expected well under a minute on
# an H100; the runs' time limits add up to under 4 minutes. The PNGs go into one tar,
# $OUT/frames_test_scenes.tar, laid out as docs/render/<scene>/frame_NNNN.png (extract it at the
# repository root), the logs beside it; a SUMMARY last, with what each scene's test measures,
# measured at the end of the drawn run ("measured:" lines).
#
#   OUT=/tmp/out bash scripts/gpu/frames_test_scenes.sh                 # configures and builds build-gpu
#   PBF_PREBUILT=.gpu-bin OUT=... bash scripts/gpu/frames_test_scenes.sh  # binaries built elsewhere
#       (as scripts/gpu/render.sh: the folder holds samples/render/pbf_render_gl and lib/)
#   PBF_BACKEND=cpu ...   runs the same on the CPU backend (the copy path; how frames were made
#       on a machine without a GPU, at PBF_SIZE=960x540)
# Exit code 0 when every run passed (and, on CUDA, took the zero-copy path).
set -uo pipefail
OUT=${OUT:-/tmp/out}
BACKEND=${PBF_BACKEND:-cuda}
SIZE=${PBF_SIZE:-1280x720}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
if [ -f .gpu-debs/setup.sh ]; then
  # shellcheck disable=SC1091
  source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
fi
device="CPU backend (copy path)"
if [ "$BACKEND" = cuda ]; then
  device=$(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1 | head -1)
fi
echo "== device: $device"

B=${PBF_PREBUILT:-build-gpu}
if [ -z "${PBF_PREBUILT:-}" ] && [ "$BACKEND" = cuda ]; then
  gen=(); command -v ninja > /dev/null && gen=(-G Ninja)
  cmake -S . -B "$B" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 > "$OUT/frames_cmake.log" 2>&1 \
    || { tail -30 "$OUT/frames_cmake.log"; echo "SUMMARY: configure failed"; exit 1; }
  cmake --build "$B" -j16 --target pbf_render_gl > "$OUT/frames_build.log" 2>&1 \
    || { grep -E "error" "$OUT/frames_build.log" | head -30; echo "SUMMARY: pbf_render_gl did not build"; exit 1; }
  echo "== build ok"
fi
R="$B/samples/render/pbf_render_gl"
[ -x "$R" ] || { echo "SUMMARY: $R is missing (PBF_PREBUILT=build-cpu for a CPU build)"; exit 1; }

STAGE="$OUT/stage"
rm -rf "$STAGE"
fail=0
results=()
# run SCENE TIMEOUT FRAMES SAVE: one scene into $STAGE/docs/render/SCENE, its log in $OUT/SCENE.log.
run() {
  local name=$1 limit=$2 frames=$3 save=$4
  local t0=$SECONDS dir="$STAGE/docs/render/$name"
  [ "$BACKEND" = cpu ] && limit=$((limit * 30)) # llvmpipe and the CPU solver: minutes, not seconds
  timeout "$limit" "$R" "$dir" --backend "$BACKEND" --scene "$name" --frames "$frames" --save "$save" \
    --size "$SIZE" > "$OUT/$name.log" 2>&1
  local rc=$?
  if [ "$BACKEND" = cuda ] && ! grep -q "GL buffers: zero-copy" "$OUT/$name.log"; then
    echo "   $name: NOT on the zero-copy path"
    [ "$rc" = 0 ] && rc=99
  fi
  [ "$rc" = 0 ] || fail=1
  echo "== $name rc=$rc ($((SECONDS - t0)) s)"
  grep -E "^($name|materials|frame loop|library host|GL buffers|measured)" "$OUT/$name.log" | cut -c1-160 | sed 's/^/   /'
  results+=("$name rc=$rc $((SECONDS - t0))s $(find "$dir" -name '*.png' 2> /dev/null | wc -l) PNGs")
  while IFS= read -r line; do results+=("  $line"); done < <(grep -E "^measured" "$OUT/$name.log")
}

run two_fluids 60 240 1,20,40,60,120,240
run droplet 40 180 1,10,20,40,90,180
run hanging_drops 40 120 1,15,30,60,120
run container 60 600 1,2,3,4,5,6,300,600
run floating_boxes 60 240 1,20,40,60,120,240

tar -cf "$OUT/frames_test_scenes.tar" -C "$STAGE" docs 2> /dev/null
pngs=$(tar -tf "$OUT/frames_test_scenes.tar" 2> /dev/null | grep -c '\.png$')
rm -rf "$STAGE"
echo
echo "SUMMARY (device: $device; $SIZE; $pngs PNGs in \$OUT/frames_test_scenes.tar, extract at the repository root):"
for r in "${results[@]}"; do echo "  $r"; done
echo "  result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
