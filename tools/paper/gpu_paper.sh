#!/usr/bin/env bash
# The GPU part of the LDC reproduction (docs/paper/README.md), for one batch on the GPU machine.
#
#   OUT=/some/dir tools/paper/gpu_paper.sh BUILD_DIR
#
# BUILD_DIR is a CUDA build of this tree (e.g. cmake -S . -B build-gpu -DPBF_CUDA_ARCHITECTURES=90
# && cmake --build build-gpu --target pbf_paper): the script runs BUILD_DIR/tools/paper/pbf_paper
# with --backend cuda and writes CSVs (and a .log per run) to $OUT. Then, on the workstation:
#
#   mkdir -p docs/paper/data/gpu && cp $OUT/*.csv $OUT/device.txt docs/paper/data/gpu/
#   tools/paper/run_report.sh --plots-only
#
# which adds the GPU timing (Fig. 2/7), the GPU method matrix and K sweep, and the finer Martin &
# Moyce curves to the report. Expected run time on an H100/H200: a few minutes.
#   1. timing: 1M particles (pbf_bench's dam column, 100 x 200 x 50), iterations 1..6, LDC off/on;
#      also 262,144 particles;
#   2. methods: dam break and resting tank at 64 particles across a (98,304 particles each),
#      PBF 1..6 iterations, LDC 1..3 iterations, 14 substeps per 1/60 s frame (the CFL-like rule);
#   3. the K sweep at 1 and 2 iterations, same scenes;
#   4. Martin & Moyce at 64, 96, 128 particles across a (up to 1.4M particles), sampled every
#      substep;
#   5. adaptive iterations (README §9): the 1M column of 1., PBF and LDC (gain 0.3) stepped
#      alternately, iterating until the mean compressive error is below η = 1 %, 0.5 %, 0.1 %
#      (cap 30 per step, as on the CPU) -> gpu_timing_adaptive.csv (iterations per step, mean
#      and max; achieved error; ms per step). About a minute.
#
# ADAPTIVE_ONLY=1 runs part 5 alone (the rest is in docs/paper/data/gpu already):
#
#   ADAPTIVE_ONLY=1 OUT=/some/dir tools/paper/gpu_paper.sh BUILD_DIR
#   cp /some/dir/gpu_timing_adaptive.csv docs/paper/data/gpu/ && tools/paper/run_report.sh --plots-only
#
# Smoke test (any machine): BACKEND=cpu RUN_EXTRA="--frames 1 --na 8 --nz 2" TIMING_EXTRA="--particles 512
# --steps 2 --warmup 1" runs every command with those arguments appended (the last value wins).
set -uo pipefail
BACKEND=${BACKEND:-cuda}
RUN_EXTRA=${RUN_EXTRA:-}
TIMING_EXTRA=${TIMING_EXTRA:-}
BUILD=${1:?usage: OUT=dir tools/paper/gpu_paper.sh BUILD_DIR}
OUT=${OUT:-/tmp/out}
BIN=$BUILD/tools/paper/pbf_paper
[[ -x "$BIN" ]] || { echo "gpu_paper.sh: $BIN not found (build the pbf_paper target with CUDA)" >&2; exit 1; }
mkdir -p "$OUT"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader > "$OUT/device.txt" 2>&1 ||
  echo "no nvidia-smi ($BACKEND backend)" > "$OUT/device.txt"
cat "$OUT/device.txt"
failures=0
source "$(dirname "${BASH_SOURCE[0]}")/k_sweep.sh"  # k_sweep BASE

# DEADLINE (epoch seconds, optional): runs and timings not started by then are skipped and
# counted as failures, so that a batch under a device call's time limit still ends in time.
late() {
  if [[ -n "${DEADLINE:-}" && $(date +%s) -ge $DEADLINE ]]; then
    echo "$1: SKIPPED (DEADLINE)"; failures=$((failures + 1)); return 0
  fi
  return 1
}

run() {  # run NAME ARGS...
  local name=$1; shift
  late "$name" && return
  if "$BIN" run --backend "$BACKEND" "$@" $RUN_EXTRA --csv "$OUT/$name.csv" > "$OUT/$name.log" 2>&1; then
    echo "$name: $(tail -1 "$OUT/$name.log" | sed 's/^ *//')"
  else
    echo "$name: FAILED (see $name.log)"; tail -3 "$OUT/$name.log"; failures=$((failures + 1))
  fi
}

# 5. Adaptive iterations on the 1M column (PBF and LDC 0.3 alternated; one substep per step).
adaptive() {
  late gpu_timing_adaptive && return
  if "$BIN" timing --backend "$BACKEND" --particles 1000000 --iterations 30 --adaptive-target 0.01,0.005,0.001 \
       --ldc 0,1 --gain 0.3 --steps 100 --warmup 20 $TIMING_EXTRA --csv "$OUT/gpu_timing_adaptive.csv" \
       > "$OUT/gpu_timing_adaptive.log" 2>&1; then
    cat "$OUT/gpu_timing_adaptive.log"
  else
    echo "gpu_timing_adaptive: FAILED"; tail -3 "$OUT/gpu_timing_adaptive.log"; failures=$((failures + 1))
  fi
}
if [[ "${ADAPTIVE_ONLY:-0}" == 1 ]]; then
  adaptive
  echo "gpu_paper.sh: done (adaptive only), $failures failure(s); CSVs in $OUT"
  exit $((failures > 0))
fi

# 1. Time per step against iterations (one substep per step, median of 100 after 20 warm-up).
for spec in "1000000 gpu_timing" "262144 gpu_timing_262k"; do
  set -- $spec
  late "$2" && continue
  if "$BIN" timing --backend "$BACKEND" --particles "$1" --iterations 1,2,3,4,5,6 --ldc 0,1 --steps 100 --warmup 20 \
       $TIMING_EXTRA --csv "$OUT/$2.csv" > "$OUT/$2.log" 2>&1; then
    cat "$OUT/$2.log"
  else
    echo "$2: FAILED"; tail -3 "$OUT/$2.log"; failures=$((failures + 1))
  fi
done

# 2. Methods (same scenes as the CPU report, twice the resolution).
BASE="--a 0.4 --na 64 --nz 12 --length 5"
for it in 1 2 3 4 5 6; do
  run dam_conv$it  --scene dam  $BASE --iterations $it --ldc 0 --frames 90
  run tank_conv$it --scene tank $BASE --iterations $it --ldc 0 --frames 60
done
for it in 1 2 3; do
  run dam_ldc$it  --scene dam  $BASE --iterations $it --ldc 1 --gain 0.1 --frames 90
  run tank_ldc$it --scene tank $BASE --iterations $it --ldc 1 --gain 0.1 --frames 60
done

# 3. K sweep.
k_sweep "$BASE"

# 4. Martin & Moyce, finer than the CPU can afford (thickness a/3 as on the CPU).
for res in "64 21" "96 32" "128 43"; do
  set -- $res
  run mm_ldc4_na$1  --scene dam --a 0.4 --na $1 --nz $2 --length 5 --iterations 4 --ldc 1 --frames 40 --per-substep 1
  run mm_conv4_na$1 --scene dam --a 0.4 --na $1 --nz $2 --length 5 --iterations 4 --ldc 0 --frames 40 --per-substep 1
done

adaptive

echo "gpu_paper.sh: done, $failures failure(s); CSVs in $OUT"
exit $((failures > 0))
