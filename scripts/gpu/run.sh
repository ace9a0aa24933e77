#!/usr/bin/env bash
# One call on the GPU machine: build for sm_90, run the [gpu] suite, the LDC/PBF unit tests,
# the 256k dam-break sample and pbf_bench; logs and the CSV go to $OUT, a short table last.
set -uo pipefail
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
GEN=""; command -v ninja >/dev/null && GEN="-G Ninja"
cmake -S . -B build-gpu $GEN -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 > "$OUT/cmake.log" 2>&1 || { tail -30 "$OUT/cmake.log"; exit 1; }
cmake --build build-gpu -j16 > "$OUT/build.log" 2>&1 || { grep -E "error" "$OUT/build.log" | head -30; exit 1; }
echo "== build ok"
ctest --test-dir build-gpu -L gpu --output-on-failure > "$OUT/ctest_gpu.log" 2>&1; echo "ctest gpu rc=$?"; tail -5 "$OUT/ctest_gpu.log"
build-gpu/tests/pbf_gpu_tests -d yes > "$OUT/gpu_tests.log" 2>&1; echo "gpu tests rc=$?"; grep -E "difference|FAILED|expansion|passed|failed|s: " "$OUT/gpu_tests.log" | head -30
PBF_BACKEND=cuda build-gpu/samples/dam_break 262144 100 4 > "$OUT/sample_256k_it4.log" 2>&1; echo "sample rc=$?"; tail -4 "$OUT/sample_256k_it4.log"
PBF_BACKEND=cuda PBF_LDC=0 build-gpu/samples/dam_break 262144 100 4 > "$OUT/sample_256k_it4_noldc.log" 2>&1; tail -1 "$OUT/sample_256k_it4_noldc.log"
build-gpu/tools/bench/pbf_bench --backend cuda --scene dam,tank --particles 65536,262144,1000000,4096000,16000000 --iterations 4 --ldc 0,1 --csv "$OUT/bench_sizes.csv" > "$OUT/bench_sizes.md" 2>&1; echo "bench sizes rc=$?"
build-gpu/tools/bench/pbf_bench --backend cuda --scene dam --particles 1000000 --iterations 1,2,3,4,5,6 --ldc 0,1 --stages --csv "$OUT/bench_iters.csv" > "$OUT/bench_iters.md" 2>&1; echo "bench iters rc=$?"
cat "$OUT/bench_sizes.md"
cat "$OUT/bench_iters.md"
