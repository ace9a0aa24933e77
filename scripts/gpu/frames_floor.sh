#!/usr/bin/env bash
# One call on the GPU machine: everything the frame goals are judged by (docs/perf.md, "Frames
# at the floor"). pbf_bench --stages at 262k and 1M; the step of a world without colliders or
# materials against a build with both compiled out (PBF_FEATURELESS_BUILD, cmake
# -DPBF_FEATURELESS=ON), alternating; the host time of queuing a step with and without the step
# graph (PBF_CUDA_GRAPHS=0); the [gpu] suite; then the frame matrix at fine 262k, game 262k and
# fine 1M (scripts/gpu/frames.sh fine, game, 1m), the defaults' cells included.
#
#   OUT=/tmp/out PBF_PREBUILT=.gpu-bin/new PBF_FEATURELESS_BUILD=.gpu-bin/fl bash scripts/gpu/frames_floor.sh
#
# Both builds: -DPBF_CUDA_ARCHITECTURES=90 -DCMAKE_BUILD_RPATH_USE_ORIGIN=ON (targets pbf
# pbf_bench pbf_frames pbf_gpu_tests; pbf_bench alone in the featureless one).
set -uo pipefail
OUT=${OUT:-/tmp/out}
B=${PBF_PREBUILT:-.gpu-bin/new}
FL=${PBF_FEATURELESS_BUILD:-}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
# PBF_GPU_DEBS: where ../shared/gpu/fetch-debs.sh put the loaders (default .gpu-debs).
D=${PBF_GPU_DEBS:-.gpu-debs}
[ -f "$D/setup.sh" ] && source "$D/setup.sh" "$D" > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
bench() { LD_LIBRARY_PATH="$1/lib" "$1/tools/bench/pbf_bench" --backend cuda "${@:2}"; }
t0=$SECONDS
bench "$B" --scene dam,tank --particles 262144,1000000 --iterations 2,4 --ldc 0,1 --stages \
  --csv "$OUT/bench_stages.csv" > "$OUT/bench_stages.md" 2>&1
echo "stages rc=$? ($((SECONDS - t0)) s)"; grep -A12 "Per-stage" "$OUT/bench_stages.md" | cut -c1-200
if [ -n "$FL" ]; then
  for rep in 1 2; do
    for v in normal featureless; do
      d=$B; [ $v = featureless ] && d=$FL
      bench "$d" --scene dam,tank --particles 262144,1000000 --iterations 4 --ldc 0,1 \
        --csv "$OUT/bench_${v}_$rep.csv" > "$OUT/bench_${v}_$rep.md" 2>&1
      echo "== $v rep $rep"; grep -E "^\| (dam|tank) " "$OUT/bench_${v}_$rep.md" | awk -F'|' '{print $2,$3,$5,$10}'
    done
  done
fi
PBF_CUDA_GRAPHS=0 bench "$B" --scene dam --particles 262144,1000000 --iterations 2,4 --ldc 1 \
  --csv "$OUT/bench_launched.csv" > "$OUT/bench_launched.md" 2>&1
bench "$B" --scene dam --particles 262144,1000000 --iterations 2,4 --ldc 1 \
  --csv "$OUT/bench_graphed.csv" > "$OUT/bench_graphed.md" 2>&1
for v in launched graphed; do
  echo "== $v (ms median, call ms)"; grep -E "^\| dam " "$OUT/bench_$v.md" | awk -F'|' '{print $3,$4,$10,$24}'
done
LD_LIBRARY_PATH="$B/lib" "$B/tests/pbf_gpu_tests" "[gpu]" > "$OUT/gpu_suite.log" 2>&1
echo "gpu suite rc=$?"; grep -E "FAILED|test cases|assertions" "$OUT/gpu_suite.log" | tail -8
export LD_LIBRARY_PATH="$B/lib"
OUT="$OUT/frames" PBF_PREBUILT="$B" bash scripts/gpu/frames.sh fine game 1m
(cd "$OUT" && tar czf /tmp/results.tgz --exclude results.tgz . && find . -mindepth 1 -delete && mv /tmp/results.tgz .)
