#!/usr/bin/env bash
# Builds libpbf (scripts/build.sh, into build/) and runs the headless dam break sample:
#
#   scripts/run_sample.sh [particles=32768] [steps=300] [iterations=4]
#
# The arguments go to build/samples/dam_break unchanged. It runs on CUDA when the library was
# built with it and a device is present, else on the CPU; PBF_BACKEND=cpu|cuda overrides, and
# PBF_LDC=0 turns Local Density Calibration off. The defaults take a few minutes on a 2-core
# CPU; `scripts/run_sample.sh 8000 120` is a quick run.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh" "$root/build"
echo
echo "== build/samples/dam_break $*"
exec "$root/build/samples/dam_break" "$@"
