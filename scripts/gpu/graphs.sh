#!/usr/bin/env bash
# One call on the GPU machine: a step queued as one CUDA graph against the same step launched
# kernel by kernel (PBF_CUDA_GRAPHS=0), same binaries, same card. The graph test of the [gpu]
# suite (or PBF_GPU_TEST_SPEC), pbf_bench at 262k and 1M (dam, 2 and 4 iterations, LDC on) with
# the two alternating, and single frame-benchmark runs of the cheapest stable cells and the
# defaults (PBF_FRAME_CELLS: "scene:scale:particles:substeps:iterations:ldc ...").
#
#   OUT=/tmp/out PBF_PREBUILT=.gpu-bin/new bash scripts/gpu/graphs.sh
set -uo pipefail
OUT=${OUT:-/tmp/out}
B=${PBF_PREBUILT:-.gpu-bin/new}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
[ -f .gpu-debs/setup.sh ] && source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
export LD_LIBRARY_PATH="$B/lib:${LD_LIBRARY_PATH:-}"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
t0=$SECONDS
"$B/tests/pbf_gpu_tests" "${PBF_GPU_TEST_SPEC:-CUDA: a step queued as one graph*}" > "$OUT/gpu_tests.log" 2>&1
echo "gpu tests rc=$? ($((SECONDS - t0)) s)"; grep -E "FAILED|passed|failed|test cases" "$OUT/gpu_tests.log" | tail -12
for rep in ${PBF_REPS:-1 2}; do
  for g in 0 1; do
    PBF_CUDA_GRAPHS=$g "$B/tools/bench/pbf_bench" --backend cuda --scene dam --particles ${PBF_BENCH_SIZES:-262144,1000000} \
      --iterations 2,4 --ldc 1 --csv "$OUT/bench_graphs${g}_${rep}.csv" > "$OUT/bench_graphs${g}_${rep}.md" 2>&1
    echo "== bench graphs=$g rep $rep rc=$?"; grep -E "^\| dam " "$OUT/bench_graphs${g}_${rep}.md" | cut -c1-120
  done
done
cells=${PBF_FRAME_CELLS:-"dam:fine:262144:7:2:1 tank:fine:262144:7:2:1 dam:game:262144:2:4:1 tank:game:262144:2:4:1 dam:fine:262144:auto:4:1 tank:fine:262144:auto:4:1 dam:game:262144:auto:4:1"}
for g in 0 1; do
  for cell in $cells; do
    IFS=: read -r scene scale n s it ldc <<< "$cell"
    PBF_CUDA_GRAPHS=$g "$B/tools/frames/pbf_frames" run --backend cuda --scene "$scene" --scale "$scale" \
      --particles "$n" --substeps "$s" --iterations "$it" --ldc "$ldc" --budget-s 20 2>/dev/null | tail -1 |
      sed "s/^/graphs=$g,/" >> "$OUT/frames.csv"
  done
done
cut -d, -f1-9,10,12 "$OUT/frames.csv"
(cd "$OUT" && tar czf /tmp/results.tgz --exclude results.tgz . && find . -mindepth 1 -delete && mv /tmp/results.tgz .)
