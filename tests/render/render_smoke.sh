#!/usr/bin/env bash
# The headless renderer on the CPU backend (copy path) with whatever EGL the machine has (Mesa's
# llvmpipe on a machine without a GPU): a small dam break drawn as a surface, its last frame
# compared with its background (the fluid must cover part of it), two fluids coloured by
# material, a glass mesh container, then the sphere mode.
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
# No amber in one-material water (the negative control of the material check below).
"$coverage" "$out/surface/frame_0010.png" "$out/surface/background.png" 0 0.002 warm || exit 1
# Two materials: the amber 500 kg/m³ fluid beside the water in the lock exchange shows
# amber (through the ids -> material table), and the water stays blue.
"$renderer" "$out/materials" --backend cpu --scene two_fluids --frames 2 --save 2 --size 128x96 --write-background \
  || { echo "render smoke test: pbf_render_gl (two_fluids) failed"; exit 1; }
"$coverage" "$out/materials/frame_0002.png" "$out/materials/background.png" 0.02 0.4 warm || exit 1
"$coverage" "$out/materials/frame_0002.png" "$out/materials/background.png" 0.02 0.4 cool || exit 1
# Colliders: the glass mesh container with its water, moved by the engine.
"$renderer" "$out/container" --backend cpu --scene container --frames 2 --save 2 --size 128x96 --write-background \
  || { echo "render smoke test: pbf_render_gl (container) failed"; exit 1; }
"$coverage" "$out/container/frame_0002.png" "$out/container/background.png" 0.002 0.3 || exit 1
"$renderer" "$out/spheres" --backend cpu --mode spheres --particles 3000 --frames 4 --every 4 --size 128x96 \
  || { echo "render smoke test: pbf_render_gl (spheres) failed"; exit 1; }
test -s "$out/spheres/frame_0004.png" || { echo "render smoke test: no spheres frame"; exit 1; }
echo "render smoke test: passed"
