#!/usr/bin/env bash
# The frames of docs/render and the README, in one call on the GPU machine from the
# repository root (expected about a minute on an H100; the runs' time limits add up to under 4 minutes):
#   - a dam break and a nozzle filling a pool drawn as a screen-space surface (smoothed positions
#     + anisotropy, plus diffuse particles where libpbf has them), 1280x720, through the
#     zero-copy path (GL buffers registered with libpbf, copied GPU to GPU on each step);
#   - the same dam break as sphere impostors at one frame, for comparison;
#   - the render path's cost in surface mode at 1M particles (BENCH line);
#   - PNGs and logs to $OUT, a summary last (the zero-copy and transfer lines of each run).
#
#   OUT=/tmp/out bash scripts/gpu/render.sh                 # configures and builds build-gpu first
#   PBF_PREBUILT=.gpu-bin OUT=... bash scripts/gpu/render.sh
#       uses binaries built on a machine without a GPU (configured with
#       -DPBF_CUDA_ARCHITECTURES=90 -DCMAKE_BUILD_RPATH_USE_ORIGIN=ON; target pbf_render_gl);
#       the folder must hold samples/render/pbf_render_gl and lib/.
# Needs the EGL/GL loaders and libpng of .gpu-debs (sourced from .gpu-debs/setup.sh when present).
# Exit code 0 when every run passed and every run took the zero-copy path.
set -uo pipefail
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
if [ -f .gpu-debs/setup.sh ]; then
  # shellcheck disable=SC1091
  source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
fi
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader > "$OUT/device.txt" 2>&1
echo "== device: $(head -1 "$OUT/device.txt")"

B=${PBF_PREBUILT:-build-gpu}
if [ -z "${PBF_PREBUILT:-}" ]; then
  gen=(); command -v ninja > /dev/null && gen=(-G Ninja)
  cmake -S . -B "$B" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 > "$OUT/render_cmake.log" 2>&1 \
    || { tail -30 "$OUT/render_cmake.log"; echo "SUMMARY: configure failed"; exit 1; }
  grep -E "samples/render" "$OUT/render_cmake.log" | sed 's/^-- /   /'
  cmake --build "$B" -j16 --target pbf_render_gl > "$OUT/render_build.log" 2>&1 \
    || { grep -E "error" "$OUT/render_build.log" | head -30; echo "SUMMARY: pbf_render_gl did not build"; exit 1; }
  echo "== build ok"
fi
R="$B/samples/render/pbf_render_gl"
[ -x "$R" ] || { echo "SUMMARY: $R is missing"; exit 1; }

fail=0
# run NAME TIMEOUT ARGS...: one renderer run into $OUT/NAME, its log in $OUT/NAME.log.
run() {
  local name=$1 limit=$2; shift 2
  local t0=$SECONDS
  rm -rf "${OUT:?}/$name"
  timeout "$limit" "$R" "$OUT/$name" --backend cuda "$@" > "$OUT/$name.log" 2>&1
  local rc=$?
  if ! grep -q "GL buffers: zero-copy" "$OUT/$name.log"; then
    echo "   $name: NOT on the zero-copy path"
    [ "$rc" = 0 ] && rc=99
  fi
  [ "$rc" = 0 ] || fail=1
  echo "== $name rc=$rc ($((SECONDS - t0)) s)"
  grep -E "^(dam break|pool|frame loop|library host|GL buffer|BENCH)" "$OUT/$name.log" | sed 's/^/   /'
}

run render_dam 60 --scene dam --mode surface --particles 200000 --frames 150 --save 20,40,60,90,150 --size 1280x720
run render_pool 70 --scene pool --mode surface --particles 300000 --frames 300 --save 60,120,180,240,300 \
  --size 1280x720
run render_dam_spheres 40 --scene dam --mode spheres --particles 200000 --frames 40 --save 40 --size 1280x720
run render_bench 60 --scene dam --mode surface --particles 65536 --frames 1 --save 1 --size 640x360 \
  --bench 1000000 --bench-frames 30

# The README's top image: the dam break's front hitting the far wall.
[ -f "$OUT/render_dam/frame_0040.png" ] && cp "$OUT/render_dam/frame_0040.png" "$OUT/readme_top.png"
pngs=$(find "$OUT" -name '*.png' 2> /dev/null | wc -l)
echo
echo "SUMMARY (device: $(head -1 "$OUT/device.txt"))"
for n in render_dam render_pool render_dam_spheres render_bench; do
  echo "  $n: $(tail -1 "$OUT/$n.log" 2> /dev/null); $(grep -h -m1 -E '^GL buffers' "$OUT/$n.log" 2> /dev/null | cut -c1-60)"
done
echo "  diffuse particles: $(grep -h -o -m1 'diffuse particles: .*' "$OUT/render_dam.log" 2> /dev/null)"
echo "  render path cost: $(grep -h '^BENCH' "$OUT/render_bench.log" 2> /dev/null)"
echo "  PNG frames in \$OUT: $pngs (render_dam/, render_pool/, render_dam_spheres/, readme_top.png)"
echo "  result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
