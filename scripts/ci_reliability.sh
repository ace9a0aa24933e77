#!/usr/bin/env bash
# Reliability checks, for CI after the main tests (.ci/run calls it), or by hand:
#
#   bash scripts/ci_reliability.sh
#
#   1. fuzz      build-fuzz/: the libFuzzer target of the C ABI (clang, ASan + UBSan), replays
#                the regression inputs (tests/fuzz/regressions) and the seed corpus, then fuzzes
#                for PBF_FUZZ_SECONDS (default 60). The long run: tests/fuzz/README.md.
#   2. sanitize  build-asan/: the CPU test suite under ASan + UBSan (-DPBF_SANITIZE=ON,
#                -DPBF_WITH_CUDA=OFF), then ctest there.
#   3. soak      build-soak/: pbf_soak (Release, CPU) for PBF_SOAK_STEPS steps (default 20000) of a
#                tiny nozzle-and-drain world: no NaN, exact accounting, flat RSS.
#
# Environment:
#   PBF_FUZZ_SECONDS        fuzzing time of step 1 (default 60)
#   PBF_SOAK_STEPS          steps of step 3 (default 20000)
#   PBF_ASAN_CTEST_EXCLUDE  ctest -E regex of tests skipped under ASan (default: none)
#   PBF_RELIABILITY_SKIP    comma list of parts to skip: fuzz,sanitize,soak
#   PBF_JOBS                build parallelism (default: nproc)
#   PBF_WARNINGS_AS_ERRORS  ON: the three builds compile with -Werror (.ci/run sets it, as for
#                           the main build; default OFF, so a newer compiler's warning run by
#                           hand does not stop the checks)
# Missing clang / libFuzzer runtime are installed with apt-get (as root, or with sudo).
# Exits non-zero if a part fails; a summary comes last.
set -uo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root" || exit 1
jobs="${PBF_JOBS:-$(nproc)}"
fuzz_seconds="${PBF_FUZZ_SECONDS:-60}"
soak_steps="${PBF_SOAK_STEPS:-20000}"
skip=",${PBF_RELIABILITY_SKIP:-},"
werror="-DPBF_WARNINGS_AS_ERRORS=${PBF_WARNINGS_AS_ERRORS:-OFF}"
declare -a summary=()
failed=0

note() { summary+=("$1"); echo "$1"; }
fail() { note "$1"; failed=1; }
# verdict PART RC OK FAILED: the part's summary line, "PART: ok: OK" when RC is 0, else
# "PART: FAILED<FAILED>" (a failure); part names padded to one column.
verdict() {
  local label
  label="$(printf '%-9s' "$1:")"
  if [ "$2" -eq 0 ]; then note "$label ok: $3"; else fail "$label FAILED$4"; fi
}
skipped() { [[ "$skip" == *",$1,"* ]]; }

ensure_packages() {  # installs missing Debian packages (quietly)
  local missing=() p
  for p in "$@"; do
    dpkg -s "$p" 2>/dev/null | grep -q '^Status: install ok installed' || missing+=("$p")
  done
  [ "${#missing[@]}" -eq 0 ] && return 0
  command -v apt-get >/dev/null 2>&1 || { echo "ci_reliability.sh: missing ${missing[*]} and no apt-get" >&2; return 1; }
  local sudo=()
  [ "$(id -u)" -ne 0 ] && sudo=(sudo)
  echo "ci_reliability.sh: installing ${missing[*]}"
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q >/dev/null 2>&1
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${missing[@]}" >/dev/null 2>&1
}

# configure_build DIR TARGET CMAKE_ARGS...: configures DIR with CMAKE_ARGS and builds TARGET ("":
# all), logs in DIR/ci_cmake.log and DIR/ci_build.log; on failure shows the errors (or the logs'
# tails where no line says error) and returns 1. Compilers come from CC/CXX, as cmake reads them.
configure_build() {
  local dir=$1 target=$2 target_args=()
  shift 2
  [ -n "$target" ] && target_args=(--target "$target")
  mkdir -p "$dir"
  if ! cmake -S . -B "$dir" "$@" >"$dir/ci_cmake.log" 2>&1 ||
     ! cmake --build "$dir" "${target_args[@]}" -j"$jobs" >"$dir/ci_build.log" 2>&1; then
    if grep -q -E 'error|Error' "$dir/ci_cmake.log" "$dir/ci_build.log"; then
      grep -E 'error|Error' "$dir/ci_cmake.log" "$dir/ci_build.log" | head -30
    else
      tail -30 "$dir/ci_cmake.log" "$dir/ci_build.log"
    fi
    return 1
  fi
}

# ---- 1. fuzz -----------------------------------------------------------------------------------
if skipped fuzz; then
  note "fuzz:     skipped"
else
  echo "== fuzz: libFuzzer target of the C ABI (build-fuzz/, clang, ASan + UBSan)"
  if ! { command -v clang++ >/dev/null 2>&1 && [ -n "$(ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a 2>/dev/null)" ]; }; then
    ensure_packages clang libclang-rt-14-dev libomp-14-dev || true
  fi
  fuzz_log=build-fuzz/ci_fuzz.log
  if ! CC=clang CXX=clang++ configure_build build-fuzz pbf_fuzz_c_api -DCMAKE_BUILD_TYPE=RelWithDebInfo \
         -DPBF_BUILD_FUZZ=ON -DPBF_WITH_CUDA=OFF -DPBF_BUILD_TESTS=OFF -DPBF_BUILD_SAMPLES=OFF "$werror"; then
    fail "fuzz:     FAILED to build (build-fuzz/ci_build.log)"
  else
    fuzzer=build-fuzz/tests/fuzz/pbf_fuzz_c_api
    mkdir -p build-fuzz/corpus build-fuzz/artifacts
    # Every past finding and every seed must run clean.
    if ! "$fuzzer" tests/fuzz/regressions/* tests/fuzz/corpus/* >build-fuzz/ci_replay.log 2>&1; then
      grep -v '^INFO' build-fuzz/ci_replay.log | tail -40
      fail "fuzz:     FAILED replaying tests/fuzz/regressions and the seed corpus (build-fuzz/ci_replay.log)"
    else
      # New units go to build-fuzz/corpus (the first directory); the repo's seeds are read only.
      "$fuzzer" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2560 -print_final_stats=1 \
        -artifact_prefix=build-fuzz/artifacts/ build-fuzz/corpus tests/fuzz/corpus >"$fuzz_log" 2>&1
      rc=$?
      execs="$(grep -m1 'stat::number_of_executed_units' "$fuzz_log" | awk '{print $2}')"
      rate="$(grep -m1 'stat::average_exec_per_sec' "$fuzz_log" | awk '{print $2}')"
      [ "$rc" -eq 0 ] || grep -v -E '^(INFO|#[0-9]+)' "$fuzz_log" | tail -40
      verdict fuzz "$rc" \
        "${execs:-?} executions in ${fuzz_seconds} s (${rate:-?}/s), $(ls tests/fuzz/regressions | wc -l) regression inputs replayed, corpus $(ls build-fuzz/corpus | wc -l) units" \
        " after ${execs:-?} executions: $(ls build-fuzz/artifacts | head -3 | tr '\n' ' ')(build-fuzz/artifacts, $fuzz_log)"
    fi
  fi
fi

# ---- 2. sanitizers -----------------------------------------------------------------------------
if skipped sanitize; then
  note "sanitize: skipped"
else
  echo
  echo "== sanitize: CPU test suite under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)"
  if ! configure_build build-asan "" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPBF_SANITIZE=ON -DPBF_WITH_CUDA=OFF \
         -DPBF_BUILD_SAMPLES=OFF "$werror"; then
    fail "sanitize: FAILED to build (build-asan/ci_build.log)"
  else
    # allocator_may_return_null: the out-of-memory tests ask for more than the machine has and
    # expect PBF_ERROR_OUT_OF_MEMORY, not an ASan abort. detect_leaks: LeakSanitizer at exit.
    export ASAN_OPTIONS="allocator_may_return_null=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    asan_log=build-asan/ci_ctest.log
    exclude=()
    [ -n "${PBF_ASAN_CTEST_EXCLUDE:-}" ] && exclude=(-E "$PBF_ASAN_CTEST_EXCLUDE")
    start=$(date +%s)
    ctest --test-dir build-asan --output-on-failure --no-tests=error -j"$jobs" --timeout 1500 "${exclude[@]}" \
      >"$asan_log" 2>&1
    rc=$?
    secs=$(( $(date +%s) - start ))
    line="$(grep -E 'tests passed, [0-9]+ tests? failed out of' "$asan_log" | tail -n 1)"
    findings="$(grep -c -E 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:' "$asan_log")"
    [ "$rc" -eq 0 ] || grep -E -A12 'ERROR: (AddressSanitizer|LeakSanitizer)|runtime error:|\*\*\*Failed|FAILED:' "$asan_log" | head -60
    verdict sanitize "$rc" "${line} under ASan+UBSan, $findings sanitizer reports, $secs s" \
      ": ${line:-no ctest summary} ($findings sanitizer reports, $secs s, $asan_log)"
  fi
fi

# ---- 3. soak -----------------------------------------------------------------------------------
if skipped soak; then
  note "soak:     skipped"
else
  echo
  echo "== soak: pbf_soak, $soak_steps steps of a nozzle-and-drain world (build-soak/, Release)"
  if ! configure_build build-soak pbf_soak -DCMAKE_BUILD_TYPE=Release -DPBF_WITH_CUDA=OFF -DPBF_BUILD_TESTS=OFF \
         -DPBF_BUILD_SAMPLES=OFF -DPBF_BUILD_SOAK=ON "$werror"; then
    fail "soak:     FAILED to build (build-soak/ci_build.log)"
  else
    soak_log=build-soak/ci_soak.log
    warmup=$(( soak_steps / 4 ))
    build-soak/tools/soak/pbf_soak --steps "$soak_steps" --check-every 500 --warmup "$warmup" --quiet >"$soak_log" 2>&1
    rc=$?
    [ "$rc" -eq 0 ] || tail -20 "$soak_log"
    verdict soak "$rc" "$(grep -m1 'pbf_soak: OK' "$soak_log" | sed 's/^pbf_soak: OK: //')" " ($soak_log)"
  fi
fi

echo
echo "== reliability summary"
printf '%s\n' "${summary[@]}"
if [ "$failed" -ne 0 ]; then
  echo "ci_reliability.sh: FAILED"
  exit 1
fi
echo "ci_reliability.sh: all passed"
