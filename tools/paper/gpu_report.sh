#!/usr/bin/env bash
# Every simulation of the LDC reproduction (docs/paper/README.md) on the CUDA backend, in one
# device call: the report's main set (tools/paper/report_runs.sh: the same scenes and resolution
# as run_report.sh's CPU route, 12,288 particles per scene), the equal-cost comparison
# (cost_runs at 64/a: 98,304 particles per scene) and the GPU set (tools/paper/gpu_paper.sh:
# 64/a methods and K sweep, timing at 262k and 1M, Martin & Moyce up to 128/a, adaptive timing).
#
#   OUT=dir [PART=1|2|all] [BUILD=.gpu-bin] [COMMIT=sha] tools/paper/gpu_report.sh
#
# BUILD: a CUDA build of this tree with the pbf_paper target (BUILD/tools/paper/pbf_paper and
# BUILD/lib/libpbf.so*). PART=1: the main set and the cost runs; PART=2: the GPU set; all (the
# default): both. Runs are staged in WORK (default /tmp/paper-report) and packed into
# $OUT/paper_data_part$PART.tar.gz (data/*.csv, data/cost/*.csv, data/gpu/*.csv, logs/) and, for
# part 1, $OUT/paper_snapshots.tar.gz (the §3 snapshots). Then, on the workstation:
#
#   tar -xzf paper_data_partall.tar.gz -C /tmp/paper && cp -r /tmp/paper/data/. docs/paper/data/
#   mkdir -p build-paper/paper-snapshots && tar -xzf paper_snapshots.tar.gz --strip-components=1 \
#       -C build-paper/paper-snapshots
#   tools/paper/run_report.sh --cpu-timing   # the CPU timing tables (§5, §9), a few minutes
#   tools/paper/run_report.sh --plots-only
#
# Smoke test on any machine: BACKEND=cpu SMOKE=1 OUT=/tmp/o tools/paper/gpu_report.sh (every run
# with --frames 1 at 8 particles across a, the timings at 512 particles: checks the arguments).
#
# Every run has a time limit (RUN_LIMIT, default 150 s), and no run starts after BUDGET seconds
# (default 420) from the start, so the archives are written inside a device call's limit; a run
# that fails, times out or is skipped is listed at the end and in logs/; the rest still come back. Exit status: the number of failures (max 1).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
BUILD=${BUILD:-.gpu-bin}
OUT=${OUT:?usage: OUT=dir [PART=1|2|all] tools/paper/gpu_report.sh}
PART=${PART:-all}
WORK=${WORK:-/tmp/paper-report}
RUN_LIMIT=${RUN_LIMIT:-150}
BUDGET=${BUDGET:-420}
export DEADLINE=$(( $(date +%s) + BUDGET ))
export BACKEND=${BACKEND:-cuda}
if [[ "${SMOKE:-0}" == 1 ]]; then
  export RUN_EXTRA="--frames 1 --na 8 --nz 2" TIMING_EXTRA="--particles 512 --steps 2 --warmup 1"
fi
RUN_EXTRA=${RUN_EXTRA:-}
BIN=$BUILD/tools/paper/pbf_paper
export LD_LIBRARY_PATH=$BUILD/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
[[ -x "$BIN" ]] || { echo "gpu_report.sh: $BIN not found (a CUDA build with the pbf_paper target)" >&2; exit 1; }
case $PART in 1|2|all) ;; *) echo "gpu_report.sh: PART must be 1, 2 or all" >&2; exit 2 ;; esac
source tools/paper/report_runs.sh  # report_runs, cost_runs
ROOT=$WORK/data
SNAP=$WORK/snapshots
LOGS=$WORK/logs
rm -rf "$WORK"
mkdir -p "$ROOT/cost" "$ROOT/gpu" "$SNAP" "$LOGS" "$OUT"
COMMIT=${COMMIT:-$(git describe --always --dirty 2>/dev/null || echo unknown)}
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader > "$ROOT/gpu/device.txt" 2>&1 ||
  echo "no nvidia-smi ($BACKEND backend)" > "$ROOT/gpu/device.txt"
cp "$ROOT/gpu/device.txt" "$ROOT/device.txt"
echo "gpu_report.sh PART=$PART started $(date -u +%Y-%m-%dT%H:%MZ) at $COMMIT on $(cat "$ROOT/device.txt")" \
  | tee "$ROOT/provenance_gpu_report.txt"
failures=0
failed=""
start=$SECONDS

# run NAME ARGS...: one simulation (CUDA unless BACKEND says otherwise) into $DATA/NAME.csv, its output into logs/NAME.log.
run() {
  local name=$1 t0=$SECONDS; shift
  if [[ $(date +%s) -ge $DEADLINE ]]; then
    echo "$name: SKIPPED (BUDGET)"; failures=$((failures + 1)); failed="$failed $name"; return
  fi
  if timeout "$RUN_LIMIT" "$BIN" run --backend "$BACKEND" "$@" $RUN_EXTRA --csv "$DATA/$name.csv" > "$LOGS/$name.log" 2>&1; then
    echo "$name ($((SECONDS - t0)) s): $(tail -1 "$LOGS/$name.log" | sed 's/^ *//')"
  else
    echo "$name: FAILED after $((SECONDS - t0)) s (logs/$name.log)"; tail -2 "$LOGS/$name.log"
    failures=$((failures + 1)); failed="$failed $name"
  fi
}

if [[ $PART == 1 || $PART == all ]]; then
  DATA=$ROOT
  report_runs
  echo "== main set done at $((SECONDS - start)) s"
  DATA=$ROOT/cost
  cost_runs "--a 0.4 --na 64 --nz 12 --length 5"
  echo "== cost runs done at $((SECONDS - start)) s"
  tar -czf "$OUT/paper_snapshots.tar.gz" -C "$WORK" snapshots
fi
if [[ $PART == 2 || $PART == all ]]; then
  OUT="$ROOT/gpu" bash tools/paper/gpu_paper.sh "$BUILD" 2>&1 | tee "$LOGS/gpu_paper.log"
  [[ ${PIPESTATUS[0]} == 0 ]] || { failures=$((failures + 1)); failed="$failed gpu_paper.sh"; }
  mkdir -p "$LOGS/gpu" && mv "$ROOT"/gpu/*.log "$LOGS/gpu/" 2>/dev/null
  echo "== GPU set done at $((SECONDS - start)) s"
fi
echo "${failed# }" | tr ' ' '\n' > "$LOGS/failed.txt"
echo "gpu_report.sh PART=$PART finished $(date -u +%Y-%m-%dT%H:%MZ) after $((SECONDS - start)) s," \
  "$failures failure(s) (logs/failed.txt):$(echo $failed | cut -c1-300)" | tee -a "$ROOT/provenance_gpu_report.txt"
tar -czf "$OUT/paper_data_part$PART.tar.gz" -C "$WORK" data logs
ls -l "$OUT"
exit $((failures > 0))
