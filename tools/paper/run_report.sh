#!/usr/bin/env bash
# Regenerates docs/paper/ (the LDC reproduction report) in one command:
#
#   tools/paper/run_report.sh              # build (CPU), run every simulation, plot, write README
#   tools/paper/run_report.sh --plots-only # re-plot and rewrite README from docs/paper/data
#                                          # (e.g. after unpacking gpu_report.sh's archive)
#   tools/paper/run_report.sh --cpu-timing # only the CPU timing tables (§5, §9), a few minutes
#
# The same simulations run on the CUDA backend in one device call: tools/paper/gpu_report.sh.
# COST=1 adds the equal-cost runs (cost_runs) at this resolution to docs/paper/data/cost.
#
# Environment: BUILD (default build-paper: a CPU build, -DPBF_WITH_CUDA=OFF), RESUME=1 keeps
# every run whose CSV already exists, NICE (default 5). The full CPU set takes about 35 minutes
# on one core of a lightly loaded machine (the adaptive runs of section 7 about 8 of them), about
# two and a half hours on 2 cores busy with other jobs; every run is at most ~41k particles.
#
# Outputs: docs/paper/data/*.csv (one time series per run, the timing table), provenance.txt
# (appended: which commit made which run),
# docs/paper/*.png, docs/paper/README.md (from tools/paper/report_template.md). Particle
# snapshots for the splat renders go to $BUILD/paper-snapshots (not part of the report).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
BUILD=${BUILD:-build-paper}
DATA=docs/paper/data
SNAP=$BUILD/paper-snapshots
NICE=${NICE:-5}
PY=${PYTHON:-python3}
# One OpenMP thread per run: on a shared 2-core machine two spinning threads run ~3x slower
# than one. The physics does not depend on the thread count (per-particle passes, no atomics).
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}
source tools/paper/report_runs.sh  # report_runs, cost_runs (and k_sweep)

if [[ "${1:-}" == "--plots-only" ]]; then
  exec "$PY" tools/paper/plot.py --data "$DATA" --snapshots "$SNAP" --out docs/paper
fi

"$PY" -c "import matplotlib, numpy" 2>/dev/null || { echo "run_report.sh: needs python3 with matplotlib and numpy (pip install matplotlib numpy)" >&2; exit 1; }
cmake -S . -B "$BUILD" -DPBF_WITH_CUDA=OFF -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$BUILD" --target pbf_paper -j2 > /dev/null
BIN=$BUILD/tools/paper/pbf_paper
mkdir -p "$DATA" "$SNAP"
COMMIT=$(git describe --always --dirty 2>/dev/null || echo unknown)
{
  echo "run_report.sh started $(date -u +%Y-%m-%dT%H:%MZ) at $COMMIT (RESUME=${RESUME:-0}) on" \
       "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //') x $(nproc --all)," \
       "load average $(cut -d' ' -f1-3 /proc/loadavg)"
} >> "$DATA/provenance.txt"

# run NAME ARGS...: one simulation into $DATA/NAME.csv (kept with RESUME=1).
run() {
  local name=$1; shift
  if [[ "${RESUME:-0}" == 1 && -s "$DATA/$name.csv" ]]; then return; fi
  echo "== $name"
  nice -n "$NICE" "$BIN" run "$@" --csv "$DATA/$name.csv.tmp" | sed 's/^/   /'
  mv "$DATA/$name.csv.tmp" "$DATA/$name.csv"
  echo "  $name: $COMMIT $(date -u +%H:%MZ)" >> "$DATA/provenance.txt"
}

# 6. Time per step against iterations on this CPU (13,824 particles, one substep per step), and
#    §9's adaptive targets on the same column, PBF and LDC stepped alternately. A few minutes:
#    `--cpu-timing` runs only these (the GPU batch, gpu_report.sh, runs the simulations).
cpu_timing() {
  if [[ "${RESUME:-0}" != 1 || ! -s "$DATA/timing_cpu.csv" ]]; then
    echo "== timing_cpu"
    "$BIN" timing --particles 13824 --iterations 1,2,3,4,5,6 --ldc 0,1 --steps 120 --warmup 10 \
      --csv "$DATA/timing_cpu.csv.tmp" | sed 's/^/   /'
    mv "$DATA/timing_cpu.csv.tmp" "$DATA/timing_cpu.csv"
    echo "  timing_cpu: $COMMIT $(date -u +%H:%MZ)" >> "$DATA/provenance.txt"
  fi
  if [[ "${RESUME:-0}" != 1 || ! -s "$DATA/timing_cpu_adaptive.csv" ]]; then
    echo "== timing_cpu_adaptive"
    nice -n "$NICE" "$BIN" timing --particles 13824 --iterations 30 --adaptive-target 0.01,0.005,0.001 --ldc 0,1 \
      --gain 0.3 --steps 120 --warmup 10 --csv "$DATA/timing_cpu_adaptive.csv.tmp" | sed 's/^/   /'
    mv "$DATA/timing_cpu_adaptive.csv.tmp" "$DATA/timing_cpu_adaptive.csv"
    echo "  timing_cpu_adaptive: $COMMIT $(date -u +%H:%MZ)" >> "$DATA/provenance.txt"
  fi
}
if [[ "${1:-}" == "--cpu-timing" ]]; then
  cpu_timing
  exit 0
fi

report_runs  # tools/paper/report_runs.sh: §1-§4, §6, §7, §9, §10
if [[ "${COST:-0}" == 1 ]]; then
  # The equal-cost comparison at this resolution (84 runs of 2 s: hours on a loaded 2-core
  # machine); the report's cost section comes from gpu_report.sh's 64/a runs on the GPU.
  mkdir -p "$DATA/cost"
  DATA_ROOT=$DATA
  DATA=$DATA/cost
  cost_runs "--a 0.4 --na 32 --nz 6 --length 5"
  DATA=$DATA_ROOT
fi
cpu_timing

"$PY" tools/paper/plot.py --data "$DATA" --snapshots "$SNAP" --out docs/paper
