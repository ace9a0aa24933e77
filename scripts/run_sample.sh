#!/usr/bin/env bash
# Builds the headless dam break sample and the library it needs (scripts/build.sh build
# dam_break: nothing else, no tests or tools) into build/, then runs it:
#
#   scripts/run_sample.sh [particles=8000] [steps=150] [iterations=4]
#
# The arguments go to build/samples/dam_break unchanged. It runs on CUDA when the library was
# built with it and a device is present, else on the CPU; PBF_BACKEND=cpu|cuda overrides, and
# PBF_LDC=0 turns Local Density Calibration off. The default run takes about a minute on a
# 2-core CPU; `scripts/run_sample.sh 32768 300` is the larger scene (several minutes there).
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/build.sh" "$root/build" dam_break
echo
echo "== build/samples/dam_break $*"
exec "$root/build/samples/dam_break" "$@"
