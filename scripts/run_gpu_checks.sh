#!/usr/bin/env bash
# The GPU checks in one command, on a machine with an NVIDIA GPU and tmpc's
# dependencies (scripts/install_deps.sh): build with CUDA, run the CUDA tests (they
# must run, not skip) and the GPU benchmark; results with the GPU model under
# bench/results/. Extra arguments go to Google Benchmark (e.g. --benchmark_filter=batch).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DTMPC_WITH_CUDA=ON >/dev/null
exec scripts/gpu_checks_from_binaries.sh build "$@"
