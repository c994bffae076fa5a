#!/usr/bin/env bash
# Run the benchmarks and keep the JSON (with the machine described) under
# bench/results/<host>-<date>.json. Extra arguments go to Google Benchmark.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
mkdir -p bench/results
stamp="$(hostname -s)-$(date +%Y%m%d-%H%M%S)"
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -n1)
for b in tmpc_bench tmpc_bench_link tmpc_bench_solvers tmpc_bench_explicit; do
  out="bench/results/${b}-${stamp}.json"
  ./build/bench/$b --benchmark_out="$out" --benchmark_out_format=json \
    --benchmark_context=cpu_model="$cpu" --benchmark_context=kernel="$(uname -r)" \
    --benchmark_context=cores="$(nproc)" "$@"
  echo "results: $out"
done
