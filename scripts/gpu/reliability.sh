#!/usr/bin/env bash
# GPU side of the reliability checks, for the machine with the CUDA device. Assumes build-gpu/
# is configured with the CUDA backend (scripts/gpu/run.sh makes it); rebuilds pbf_gpu_tests
# incrementally (it now includes tests/test_gpu_reliability.cpp), then:
#
#   1. the [gpu] suite once, plainly (baseline: results and time);
#   2. compute-sanitizer over the [gpu] suite:
#        memcheck  (--leak-check full)        all [gpu] tests but [memory] and [interop]
#        memcheck  (--report-api-errors no)   the [memory] and [interop] tests: they provoke
#                                             cudaMalloc failures and invalid-handle errors
#                                             (GL, external memory) on purpose, which memcheck
#                                             would count; memory errors are still reported
#        initcheck, synccheck                 all [gpu] tests but [memory] (it fills the device)
#        racecheck                            the [quick] test: every kernel path a few times
#                                             (racecheck is ~100x slower; over the whole suite
#                                             it ran past 110 s on an H200)
#   3. a one-line summary per tool: "ERROR SUMMARY: N errors", the Catch2 result, exit code, time.
#
#   OUT=/tmp/out bash scripts/gpu/reliability.sh
#
# Environment:
#   OUT                      where the logs go (default /tmp/out)
#   PBF_GPU_TESTS            the test binary (default build-gpu/tests/pbf_gpu_tests)
#   PBF_GPU_FILTER           Catch2 test spec of the sanitized runs (default "[gpu]~[memory]")
#   PBF_RACECHECK_FILTER     Catch2 test spec of the racecheck run (default "[gpu][quick]")
#   PBF_SANITIZER_TOOLS      tools to run (default "memcheck racecheck initcheck synccheck")
#   PBF_SANITIZER_TIMEOUT    seconds per tool run (default 150; the device allows 10 min a command)
#   PBF_GPU_NO_BUILD=1       skip the incremental rebuild
# Exit status: 0 when every run passed with 0 sanitizer errors.
set -uo pipefail
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
cd "$(dirname "${BASH_SOURCE[0]}")/../.." || exit 1
[ -f .gpu-debs/setup.sh ] && source .gpu-debs/setup.sh .gpu-debs >"$OUT/rel_setup.log" 2>&1
export PATH="$PATH:/usr/local/cuda/bin"
tests=${PBF_GPU_TESTS:-build-gpu/tests/pbf_gpu_tests}
filter=${PBF_GPU_FILTER:-"[gpu]~[memory]"}
memcheck_filter="$filter~[interop]"
race_filter=${PBF_RACECHECK_FILTER:-"[gpu][quick]"}
tools=${PBF_SANITIZER_TOOLS:-"memcheck racecheck initcheck synccheck"}
limit=${PBF_SANITIZER_TIMEOUT:-150}
status=0
declare -a summary=()

nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>/dev/null | tee "$OUT/rel_device.txt"
if [ "${PBF_GPU_NO_BUILD:-0}" != 1 ]; then
  if ! cmake --build build-gpu --target pbf_gpu_tests -j"$(nproc)" >"$OUT/rel_build.log" 2>&1; then
    grep -E "error" "$OUT/rel_build.log" | head -30
    echo "gpu_reliability.sh: building pbf_gpu_tests failed"
    exit 1
  fi
fi
[ -x "$tests" ] || { echo "gpu_reliability.sh: $tests not found (build build-gpu first: scripts/gpu/run.sh)"; exit 1; }

sanitizer=$(command -v compute-sanitizer || true)
if [ -z "$sanitizer" ]; then
  for c in "${CUDA_HOME:-}/bin/compute-sanitizer" /usr/local/cuda*/bin/compute-sanitizer \
           /usr/local/cuda*/compute-sanitizer/compute-sanitizer /opt/nvidia/*/compute-sanitizer; do
    [ -x "$c" ] && { sanitizer=$c; break; }
  done
fi

catch_line() {  # Catch2's result line of a log
  grep -E "^(All tests passed|test cases:)" "$1" | tail -1
}

run_one() {  # name, log, command...
  local name=$1 log=$2; shift 2
  local t0=$(date +%s)
  timeout "$limit" "$@" >"$log" 2>&1
  local rc=$? secs=$(( $(date +%s) - t0 ))
  local errs
  # racecheck prints "RACECHECK SUMMARY: N hazards displayed (E errors, W warnings)"
  errs=$(grep -E "ERROR SUMMARY|RACECHECK SUMMARY" "$log" | tail -1 | sed 's/^=* *//' |
         sed -E 's/RACECHECK SUMMARY: .*\(([0-9]+) errors.*/ERROR SUMMARY: \1 errors/')
  [ -z "$errs" ] && errs="no ERROR SUMMARY"
  local line
  line=$(printf '%-24s %s | %s | rc %d | %d s' "$name:" "$errs" "$(catch_line "$log")" "$rc" "$secs")
  [ "$rc" -eq 124 ] && line="$line (TIMEOUT after $limit s)"
  summary+=("$line")
  echo "$line"
  if [ "$rc" -ne 0 ] || { [[ "$errs" != "ERROR SUMMARY: 0 errors" ]] && [[ "$name" != plain* ]]; }; then
    status=1
    grep -E -B2 -A12 "========= (Invalid|Race|Uninitialized|Barrier|Program hit|Leaked|ERROR)|FAILED:" "$log" | head -60
  fi
}

echo "== [gpu] suite, plain"
run_one "plain [gpu]" "$OUT/rel_plain.log" "$tests" "[gpu]" --durations yes

if [ -z "$sanitizer" ]; then
  echo "gpu_reliability.sh: compute-sanitizer not found (CUDA toolkit's bin/)"
  status=1
else
  echo "== compute-sanitizer ($("$sanitizer" --version | grep -m1 -i version))"
  for tool in $tools; do
    case "$tool" in
      memcheck)
        run_one "memcheck" "$OUT/rel_memcheck.log" "$sanitizer" --tool memcheck --leak-check full \
          --error-exitcode 2 "$tests" "$memcheck_filter"
        run_one "memcheck [memory]" "$OUT/rel_memcheck_oom.log" "$sanitizer" --tool memcheck --leak-check full \
          --report-api-errors no --error-exitcode 2 "$tests" "[gpu][memory]"
        run_one "memcheck [interop]" "$OUT/rel_memcheck_interop.log" "$sanitizer" --tool memcheck --leak-check full \
          --report-api-errors no --error-exitcode 2 "$tests" "[gpu][interop]"
        ;;
      racecheck)
        run_one "racecheck" "$OUT/rel_racecheck.log" "$sanitizer" --tool racecheck --racecheck-report all \
          --error-exitcode 2 "$tests" "$race_filter"
        ;;
      *)
        run_one "$tool" "$OUT/rel_$tool.log" "$sanitizer" --tool "$tool" --error-exitcode 2 "$tests" "$filter"
        ;;
    esac
  done
fi

echo
echo "== gpu reliability summary ($(head -1 "$OUT/rel_device.txt" 2>/dev/null))"
printf '%s\n' "${summary[@]}" | tee "$OUT/rel_summary.txt"
[ "$status" -eq 0 ] && echo "gpu_reliability.sh: all passed" || echo "gpu_reliability.sh: FAILED (logs in $OUT/rel_*.log)"
exit "$status"
