#!/usr/bin/env bash
# Run the CUDA tests and the GPU benchmark from built binaries: BIN/tests/test_cuda and
# BIN/bench/tmpc_bench_cuda (a build tree, or a bundle from scripts/pack_gpu_bundle.sh).
# Fails when the tests skip (no usable GPU). Writes bench/results/tmpc_bench_cuda-*.json
# and the test log under RESULTS (default bench/results).
# With BIN/tmpc and an artifact in TMPC_ARTIFACT it then flies the thesis helix mission
# (config/scenarios/thesis_helix.yaml) with --solver admm-cuda, admm (the CPU twin of the
# same build) and auto, and keeps each flight's metrics.json under RESULTS as
# mission-SOLVER-*.json. GPU_CHECKS_SKIP_BENCH=1 leaves the benchmark out.
set -euo pipefail
bin="$1"
shift
results="${RESULTS:-bench/results}"
mkdir -p "$results"
gpu=$(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | head -n1 || echo unknown)
stamp="$(date +%Y%m%d-%H%M%S)"
tag=$(echo "$gpu" | cut -d, -f1 | tr ' ' '-' | tr -cd 'A-Za-z0-9-')
log="$results/test_cuda-${tag}-${stamp}.log"
echo "GPU: $gpu"
status=0
"$bin/tests/test_cuda" 2>&1 | tee "$log" || status=1
if grep -q "SKIPPED" "$log"; then
  echo "the CUDA tests skipped: no usable GPU here (see $log)" >&2
  exit 1
fi
if [ "${GPU_CHECKS_SKIP_BENCH:-0}" != 1 ]; then
  cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -n1)
  out="$results/tmpc_bench_cuda-${tag}-${stamp}.json"
  "$bin/bench/tmpc_bench_cuda" --benchmark_out="$out" --benchmark_out_format=json \
    --benchmark_context=gpu="$gpu" --benchmark_context=cpu_model="$cpu" --benchmark_context=cores="$(nproc)" "$@" ||
    status=1
  echo "results: $out and $log"
fi
if [ -x "$bin/tmpc" ] && [ -n "${TMPC_ARTIFACT:-}" ]; then
  src="${TMPC_SOURCE_DIR:-.}"
  "$bin/tmpc" devices || status=1
  for solver in admm-cuda admm auto; do
    dir=$(mktemp -d)
    echo "== helix mission, --solver $solver"
    "$bin/tmpc" simulate --controller "$TMPC_ARTIFACT" --scenario "$src/config/scenarios/thesis_helix.yaml" \
      --solver "$solver" --out "$dir" || status=1
    [ -f "$dir/metrics.json" ] && cp "$dir/metrics.json" "$results/mission-${solver}-${tag}-${stamp}.json"
    rm -rf "$dir"
  done
fi
exit "$status"
