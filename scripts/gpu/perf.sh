#!/usr/bin/env bash
# One call on the GPU machine, within its 10-minute limit: the [gpu] suite, pbf_bench (sizes and
# the per-stage iteration sweep), the 256k sample and, where built, variant builds of pbf_bench
# at 1M; logs and CSVs to $OUT, a short table last.
#
#   OUT=/tmp/out bash scripts/gpu/perf.sh                 # builds build-gpu there (sm_90) first
#   PBF_PREBUILT=build-sm90 OUT=... bash scripts/gpu/perf.sh
#       uses binaries built on a machine without a GPU, configured with
#       -DPBF_CUDA_ARCHITECTURES=90 -DCMAKE_BUILD_RPATH_USE_ORIGIN=ON (carry the folder);
#   PBF_VARIANTS="build-sm90-flat ..."                   more builds whose pbf_bench runs at 1M.
set -uo pipefail
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
[ -f .gpu-debs/setup.sh ] && source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
B=${PBF_PREBUILT:-build-gpu}
if [ -z "${PBF_PREBUILT:-}" ]; then
  GEN=""; command -v ninja >/dev/null && GEN="-G Ninja"
  cmake -S . -B "$B" $GEN -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 > "$OUT/cmake.log" 2>&1 || { tail -30 "$OUT/cmake.log"; exit 1; }
  cmake --build "$B" -j16 --target pbf_gpu_tests pbf_bench dam_break > "$OUT/build.log" 2>&1 || { grep -E "error" "$OUT/build.log" | head -30; exit 1; }
  echo "== build ok"
fi
t0=$SECONDS
"$B/tests/pbf_gpu_tests" "[gpu]" > "$OUT/gpu_tests.log" 2>&1; echo "gpu tests rc=$? ($((SECONDS - t0)) s)"
grep -E "difference|FAILED|passed|failed" "$OUT/gpu_tests.log" | tail -8
PBF_BACKEND=cuda "$B/samples/dam_break" 262144 100 4 > "$OUT/sample_256k_it4.log" 2>&1; echo "sample rc=$?"; tail -2 "$OUT/sample_256k_it4.log"
"$B/tools/bench/pbf_bench" --backend cuda --scene dam,tank --particles 65536,262144,1000000,4096000,16000000 --iterations 4 \
  --ldc 0,1 --csv "$OUT/bench_sizes.csv" > "$OUT/bench_sizes.md" 2>&1; echo "bench sizes rc=$?"
"$B/tools/bench/pbf_bench" --backend cuda --scene dam --particles 1000000 --iterations 1,2,3,4,5,6 --ldc 0,1 --stages \
  --csv "$OUT/bench_iters.csv" > "$OUT/bench_iters.md" 2>&1; echo "bench iters rc=$?"
# Open levels: a puddle in a walled 2 m box (dense grid) and 1 km out in an open level
# (hashed grid, five planes), and the walled box on the hashed grid.
"$B/tools/bench/pbf_bench" --backend cuda --scene puddle --particles 100000,1000000 --iterations 4 --ldc 0 \
  --level-size 0,1000 --grid auto,hashed --csv "$OUT/bench_open.csv" > "$OUT/bench_open.md" 2>&1; echo "bench open rc=$?"
for v in ${PBF_VARIANTS:-}; do
  [ -x "$v/tools/bench/pbf_bench" ] || continue
  "$v/tools/bench/pbf_bench" --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 0,1 --stages \
    --csv "$OUT/bench_$(basename "$v").csv" > "$OUT/bench_$(basename "$v").md" 2>&1
  echo "== variant $v"; grep -E "^\| dam" "$OUT/bench_$(basename "$v").md"
done
cat "$OUT/bench_sizes.md"
cat "$OUT/bench_iters.md"
cat "$OUT/bench_open.md"
