#!/usr/bin/env bash
# Zero-copy rendering on the GPU machine, in one call from the repository root:
#   - configures build-gpu (sm_90, Release) if it is not there, then builds it (incremental);
#   - runs the [interop] tests of pbf_gpu_tests (GL buffers, Vulkan external memory, device
#     pointers, the transfer counter);
#   - runs samples/render/pbf_render_gl twice (colour by speed, with the render path's cost at
#     1M particles; colour by density) and samples/render/pbf_render_vk;
#   - copies the PNG frames and every log to $OUT, and prints a short summary last.
# Needs the Debian packages of .gpu-debs (EGL/GL/Vulkan loaders and headers, libpng, Catch2):
# sourced from .gpu-debs/setup.sh when present. Exit code: 0 when everything passed.
set -uo pipefail
OUT=${OUT:-/tmp/out}
BUILD=${BUILD:-build-gpu}
mkdir -p "$OUT"
if [ -f .gpu-debs/setup.sh ]; then
  # shellcheck disable=SC1091
  source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
fi
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader > "$OUT/device.txt" 2>&1
echo "== device: $(head -1 "$OUT/device.txt")"

GEN=""; command -v ninja > /dev/null && GEN="-G Ninja"
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S . -B "$BUILD" $GEN -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 > "$OUT/interop_cmake.log" 2>&1 \
    || { tail -30 "$OUT/interop_cmake.log"; echo "SUMMARY: configure failed"; exit 1; }
else
  cmake "$BUILD" > "$OUT/interop_cmake.log" 2>&1 || { tail -30 "$OUT/interop_cmake.log"; echo "SUMMARY: configure failed"; exit 1; }
fi
grep -E "libpbf interop|samples/render" "$OUT/interop_cmake.log" | sed 's/^-- /   /'
# Only what this script runs (a half-finished target elsewhere in the tree does not stop it).
targets="pbf pbf_gpu_tests"
grep -q "samples/render: pbf_render_gl (" "$OUT/interop_cmake.log" && targets="$targets pbf_render_gl"
grep -q "samples/render: pbf_render_vk (" "$OUT/interop_cmake.log" && targets="$targets pbf_render_vk"
: > "$OUT/interop_build.log"
build_failed=""
for t in $targets; do
  cmake --build "$BUILD" -j16 --target "$t" >> "$OUT/interop_build.log" 2>&1 || build_failed="$build_failed $t"
done
if [ -n "$build_failed" ]; then
  grep -E "error" "$OUT/interop_build.log" | head -30
  echo "== build failed for:$build_failed"
  case " $build_failed " in *" pbf "*) echo "SUMMARY: the library did not build"; exit 1 ;; esac
else
  echo "== build ok ($targets)"
fi

fail=0
[ -z "$build_failed" ] || fail=1
# 1. Tests.
tests_rc=not-built
if [ -x "$BUILD/tests/pbf_gpu_tests" ] && ! echo " $build_failed " | grep -q " pbf_gpu_tests "; then
  timeout 600 "$BUILD/tests/pbf_gpu_tests" "[interop]" -d yes > "$OUT/interop_tests.log" 2>&1
  tests_rc=$?
fi
[ "$tests_rc" = 0 ] || fail=1
echo "== [interop] tests rc=$tests_rc"
grep -E "FAILED|failed|warning|WARN|not built|test cases|assertions|passed" "$OUT/interop_tests.log" 2> /dev/null | head -40

# 2. The headless GL renderer: speed colouring + the 1M cost; then density colouring.
gl_rc=skipped; gl2_rc=skipped
if [ -x "$BUILD/samples/render/pbf_render_gl" ] && ! echo " $build_failed " | grep -q " pbf_render_gl "; then
  rm -rf "$OUT/frames_speed" "$OUT/frames_density"
  timeout 600 "$BUILD/samples/render/pbf_render_gl" "$OUT/frames_speed" --particles 65536 --frames 180 --every 15 --mode spheres --backend cuda \
    --color speed --bench 1000000 --bench-frames 60 > "$OUT/render_gl.log" 2>&1
  gl_rc=$?
  timeout 300 "$BUILD/samples/render/pbf_render_gl" "$OUT/frames_density" --particles 65536 --frames 120 --every 30 --mode spheres --backend cuda \
    --color density --bench 0 > "$OUT/render_gl_density.log" 2>&1
  gl2_rc=$?
  [ "$gl_rc" = 0 ] && [ "$gl2_rc" = 0 ] || fail=1
  echo "== pbf_render_gl rc=$gl_rc (density run rc=$gl2_rc)"
  tail -12 "$OUT/render_gl.log"
else
  fail=1
  echo "== pbf_render_gl was not built (see $OUT/interop_cmake.log)"
fi

# 3. Vulkan external memory.
vk_rc=skipped
if [ -x "$BUILD/samples/render/pbf_render_vk" ] && ! echo " $build_failed " | grep -q " pbf_render_vk "; then
  timeout 300 "$BUILD/samples/render/pbf_render_vk" --particles 65536 --frames 30 > "$OUT/render_vk.log" 2>&1
  vk_rc=$?
  [ "$vk_rc" = 0 ] || fail=1
  echo "== pbf_render_vk rc=$vk_rc"
  cat "$OUT/render_vk.log"
else
  fail=1
  echo "== pbf_render_vk was not built (see $OUT/interop_cmake.log)"
fi

# Summary (last).
pngs=$(find "$OUT" -name '*.png' 2> /dev/null | wc -l)
echo
echo "SUMMARY (device: $(head -1 "$OUT/device.txt"))"
echo "  [interop] tests: rc=$tests_rc; $(grep -E '^(All tests passed|test cases:)' "$OUT/interop_tests.log" 2> /dev/null | tail -1)"
[ -z "$build_failed" ] || echo "  build failed for:$build_failed"
echo "  GL renderer: rc=$gl_rc/$gl2_rc; $(grep -h -E '^library host|^GL buffer' "$OUT/render_gl.log" 2> /dev/null | tr '\n' ' ')"
echo "  render path cost: $(grep -h '^BENCH' "$OUT/render_gl.log" 2> /dev/null)"
echo "  Vulkan: rc=$vk_rc; $(tail -1 "$OUT/render_vk.log" 2> /dev/null)"
echo "  PNG frames in \$OUT: $pngs ($OUT/frames_speed, $OUT/frames_density)"
echo "  result: $([ $fail = 0 ] && echo PASS || echo FAIL)"
exit $fail
