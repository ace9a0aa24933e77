#!/usr/bin/env bash
# Block size / register cap sweep on the GPU machine: one build per variant, in parallel, then
# pbf_bench at 1M particles, 4 iterations. Prints one line per variant.
set -uo pipefail
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
source .gpu-debs/setup.sh .gpu-debs > /dev/null 2>&1
variants="128:0 256:0 512:0 256:32 128:40"
for v in $variants; do
  b=${v%:*}; r=${v#*:}; dir=build-tune-$b-$r
  ( cmake -S . -B $dir -G Ninja -DCMAKE_BUILD_TYPE=Release -DPBF_CUDA_ARCHITECTURES=90 -DPBF_BUILD_TESTS=OFF \
      -DPBF_CUDA_BLOCK=$b $( [ "$r" != 0 ] && echo -DPBF_CUDA_MAXRREG=$r ) > "$OUT/cfg-$b-$r.log" 2>&1 &&
    cmake --build $dir -j4 --target pbf_bench > "$OUT/build-$b-$r.log" 2>&1 ) &
done
wait
for v in $variants; do
  b=${v%:*}; r=${v#*:}
  line=$(build-tune-$b-$r/tools/bench/pbf_bench --backend cuda --scene dam --particles 1000000 --iterations 4 --ldc 0,1 2>&1 | grep '^| dam' | cut -d'|' -f5,8 | tr '\n' ' ')
  echo "block $b maxrreg $r: $line"
done
