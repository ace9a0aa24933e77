#!/usr/bin/env bash
# The frame benchmark on a GPU machine, in parts that each fit one 10-minute device call.
#
#   OUT=/tmp/out PBF_PREBUILT=build-cuda bash scripts/gpu/frames.sh PART...
#
# PBF_PREBUILT: a CUDA build of this tree (-DPBF_CUDA_ARCHITECTURES=90
# -DCMAKE_BUILD_RPATH_USE_ORIGIN=ON, targets pbf_frames pbf_gpu_tests pbf_bench), carried to the
# machine. Each PART, in order (default: suite), its output in $OUT/frames_PART.log and its last
# lines with its exit status and wall time on stdout:
#   suite   the [gpu] suite and pbf_bench at 1M (dam, 4 iterations, LDC off/on)
#   fine    the matrix at fine scale, 262,144 particles (S 1,2,3,4,7,auto x iterations 1-4 x LDC),
#           then automatic substeps at 1.0 h of travel (1-2 iterations, both scales)
#   game    the matrix at game scale (2.5 cm radius), 262,144 particles
#   1m      the matrix at fine scale, 1,000,000 particles (S 4,7,auto x iterations 2,4 x LDC)
# CSVs and logs go to $OUT; docs/perf/h100_frames_*.csv are these CSVs.
set -uo pipefail
OUT=${OUT:-/tmp/out}
B=${PBF_PREBUILT:-build-cuda}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
# .gpu-debs: the loaders and libraries a bare GPU machine lacks, with setup.sh copied beside them.
[ -f .gpu-debs/setup.sh ] && source .gpu-debs/setup.sh .gpu-debs > "$OUT/setup.log" 2>&1
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee "$OUT/device.txt"
F="$B/tools/frames/pbf_frames"
part() {
  case "$1" in
    suite)
      t0=$SECONDS
      "$B/tests/pbf_gpu_tests" "[gpu]" > "$OUT/gpu_tests.log" 2>&1; echo "gpu tests rc=$? ($((SECONDS - t0)) s)"
      grep -E "FAILED|passed|failed|test cases" "$OUT/gpu_tests.log" | tail -12
      "$B/tools/bench/pbf_bench" --backend cuda --scene dam,tank --particles 1000000 --iterations 4 --ldc 0,1 \
        --csv "$OUT/bench_1m.csv" > "$OUT/bench_1m.md" 2>&1; echo "bench rc=$?"; cat "$OUT/bench_1m.md"
      ;;
    fine)
      "$F" matrix --backend cuda --sizes fine:262144 --budget-s 20 --csv "$OUT/frames_fine_262k.csv" 2>&1 | tail -4
      # Automatic substeps at 1.0 h of travel per substep (twice the default's), 1-2 iterations.
      "$F" matrix --backend cuda --sizes fine:262144,game:262144 --substeps auto --iterations 1,2 --travel 1.0 \
        --budget-s 20 --csv "$OUT/frames_travel1.csv" 2>&1 | tail -4 ;;
    game)
      "$F" matrix --backend cuda --sizes game:262144 --budget-s 20 --csv "$OUT/frames_game_262k.csv" 2>&1 | tail -4 ;;
    1m)
      "$F" matrix --backend cuda --sizes fine:1000000 --substeps 4,7,auto --iterations 2,4 --budget-s 30 \
        --csv "$OUT/frames_fine_1m.csv" 2>&1 | tail -4 ;;
  esac
}
for p in "${@:-suite}"; do
  t0=$SECONDS
  part "$p" > "$OUT/frames_$p.log" 2>&1
  echo "frames $p rc=$? ($((SECONDS - t0)) s)"; tail -3 "$OUT/frames_$p.log"
done
