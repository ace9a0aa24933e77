#!/usr/bin/env bash
# The headless renderer on the CPU backend (copy path) with whatever EGL the machine has (Mesa's
# llvmpipe on a machine without a GPU): a small dam break drawn as a surface, its last frame
# compared with its background (the fluid must cover part of it), then the sphere mode.
#   render_smoke.sh PBF_RENDER_GL PNG_COVERAGE OUT_DIR
# Exit 77 (skipped) when no EGL display can be created.
set -u
renderer=$1 coverage=$2 out=$3
rm -rf "$out"
"$renderer" "$out/surface" --backend cpu --scene dam --particles 3000 --frames 10 --save 10 --size 128x96 \
  --write-background
rc=$?
[ "$rc" = 77 ] && { echo "render smoke test: SKIPPED (no EGL display)"; exit 77; }
[ "$rc" = 0 ] || { echo "render smoke test: pbf_render_gl (surface) failed, rc=$rc"; exit 1; }
# The column of water covers roughly a tenth of this view.
"$coverage" "$out/surface/frame_0010.png" "$out/surface/background.png" 0.02 0.6 || exit 1
"$renderer" "$out/spheres" --backend cpu --mode spheres --particles 3000 --frames 4 --every 4 --size 128x96 \
  || { echo "render smoke test: pbf_render_gl (spheres) failed"; exit 1; }
test -s "$out/spheres/frame_0004.png" || { echo "render smoke test: no spheres frame"; exit 1; }
echo "render smoke test: passed"
