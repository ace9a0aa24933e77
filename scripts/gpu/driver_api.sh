#!/usr/bin/env bash
# One call on the GPU machine: the CUDA executor over the driver API against a build of the
# runtime-API executor it replaced, on the same card. The [gpu] suite on the new build, then
# pbf_bench at 1M (dam and tank, 4 iterations, LDC off/on), the two builds alternating (twice
# each) so that clock drift weighs on both; world creation times (the first with the driver
# opened and the kernels loaded); ldd of each library.
#
#   OUT=/tmp/out PBF_NEW=.gpu-bin/new PBF_OLD=.gpu-bin/old bash scripts/gpu/driver_api.sh
#
# PBF_NEW, PBF_OLD: CUDA builds (-DPBF_CUDA_ARCHITECTURES=90 -DCMAKE_BUILD_RPATH_USE_ORIGIN=ON;
# targets pbf pbf_bench, and pbf_gpu_tests in the new one) carried to the machine; .gpu-debs
# (../shared/gpu/fetch-debs.sh) for the loaders the tests link.
set -uo pipefail
OUT=${OUT:-/tmp/out}
NEW=${PBF_NEW:-.gpu-bin/new}
OLD=${PBF_OLD:-.gpu-bin/old}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
[ -f .gpu-debs/setup.sh ] && source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
for b in "$NEW" "$OLD"; do
  echo "== ldd $b/lib/libpbf.so: $(ldd "$b/lib/libpbf.so" | grep -E -o 'lib(cuda|cudart)[^ ]*' | tr '\n' ' ')"
done
if [ -x "$NEW/tests/pbf_gpu_tests" ]; then
  t0=$SECONDS
  "$NEW/tests/pbf_gpu_tests" "[gpu]" ${PBF_GPU_TEST_SPEC:-} > "$OUT/gpu_tests.log" 2>&1
  echo "gpu tests rc=$? ($((SECONDS - t0)) s)"
  grep -E "FAILED|passed|failed|test cases" "$OUT/gpu_tests.log" | tail -12
fi
for rep in ${PBF_REPS:-1 2}; do
  for b in old new; do
    dir=$OLD; [ "$b" = new ] && dir=$NEW
    "$dir/tools/bench/pbf_bench" --backend cuda --scene dam,tank --particles 1000000 --iterations 4 --ldc 0,1 \
      --csv "$OUT/bench_${b}_${rep}.csv" > "$OUT/bench_${b}_${rep}.md" 2>&1
    echo "bench $b rep $rep rc=$?"
  done
done
for f in "$OUT"/bench_*_*.md; do
  echo "== $(basename "$f")"
  grep -E "^\| (dam|tank) |^World creation" "$f" | cut -c1-140
done
if [ -n "${PBF_STAGES:-}" ]; then
  for b in old new; do
    dir=$OLD; [ "$b" = new ] && dir=$NEW
    "$dir/tools/bench/pbf_bench" --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 0 --stages \
      --csv "$OUT/stages_${b}.csv" > "$OUT/stages_${b}.md" 2>&1
    echo "== stages $b"; grep -A3 "Per-stage" "$OUT/stages_${b}.md" | tail -1 | cut -c1-220
  done
fi
if [ -n "${PBF_FRAMES:-}" ]; then
  OUT="$OUT/frames" PBF_PREBUILT="$NEW" bash scripts/gpu/frames.sh fine game 1m
fi
# The device tool returns at most 8 files: everything in one archive.
(cd "$OUT" && tar czf /tmp/results.tgz --exclude results.tgz . && find . -mindepth 1 -delete && mv /tmp/results.tgz .)
