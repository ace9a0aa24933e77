#!/usr/bin/env bash
# One call on the GPU machine with binaries built elsewhere (.gpu-bin: lib/, tests/, tools/bench/,
# samples/, samples/render/; see scripts/gpu/perf.sh): the [gpu] suite of every test binary, pbf_bench for the
# materials / render / diffuse / mesh-collider goals at 1M, and the frames of the tests' scenes.
# Everything lands in one tar, $OUT/all.tar (the device tool returns only a few files).
set -uo pipefail
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
B=.gpu-bin
t0=$SECONDS
for t in gpu coupling material mesh api unit reliability; do
  timeout 200 $B/tests/pbf_${t}_tests "[gpu]" -d yes > "$OUT/suite_$t.log" 2>&1; echo "suite $t rc=$? $((SECONDS-t0))s"; tail -3 "$OUT/suite_$t.log" | grep -E "test cases|No test"
done
grep -hE "FAILED|failed as expected" $OUT/suite_*.log | head
timeout 150 $B/tools/bench/pbf_bench --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 1 --materials 1,2 --stages --csv "$OUT/bench_materials.csv" > "$OUT/bench_materials.md" 2>&1; echo "bench materials rc=$? $((SECONDS-t0))s"
timeout 150 $B/tools/bench/pbf_bench --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 1 --diffuse 0,1000000 --render 0,1 --stages --csv "$OUT/bench_diffuse.csv" > "$OUT/bench_diffuse.md" 2>&1; echo "bench diffuse rc=$? $((SECONDS-t0))s"
timeout 100 $B/tools/bench/pbf_bench --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 1 --collider none,box,mesh --csv "$OUT/bench_mesh.csv" > "$OUT/bench_mesh.md" 2>&1; echo "bench mesh rc=$? $((SECONDS-t0))s"
cat "$OUT/bench_materials.md" "$OUT/bench_diffuse.md" "$OUT/bench_mesh.md" | cut -c1-400
if [ $((SECONDS-t0)) -lt 330 ]; then
  PBF_PREBUILT=.gpu-bin OUT="$OUT/frames" timeout 200 bash scripts/gpu/frames_test_scenes.sh > "$OUT/frames.txt" 2>&1; echo "frames rc=$?"; tail -25 "$OUT/frames.txt"
fi
cd "$OUT" && tar -cf all.tar --exclude=all.tar . && find . -mindepth 1 ! -name all.tar ! -name device.txt -delete
echo "done $((SECONDS-t0))s: $OUT/all.tar"
