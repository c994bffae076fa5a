#!/usr/bin/env bash
# Explicit MPC scaling: region count and build time against the horizon (M = 1 and 2)
# and the parameter box, on the default design. Writes a table to
# bench/results/explicit_scaling-<host>-<date>.txt. Usage: scripts/explicit_scaling.sh [ARTIFACT]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh >/dev/null
artifact="${1:-out/tiltrotor.tmpc}"
if [ ! -f "$artifact" ]; then
  mkdir -p "$(dirname "$artifact")"
  ./build/tmpc design --config config/tiltrotor.yaml --out "$artifact" >/dev/null
fi
mkdir -p bench/results
out="bench/results/explicit_scaling-$(hostname -s)-$(date +%Y%m%d-%H%M%S).txt"
tmp="$(mktemp -d)"
{
  echo "# tmpc explicit on $(lscpu | sed -n 's/^Model name: *//p' | head -n1), $(nproc) cores"
  printf "%-4s %-4s %-8s %-8s %-10s %-9s %-8s %-10s %-8s\n" N M box regions complete build_s tree_s tree_depth KiB
  for cfg in "1 1 0.2" "1 1 0.5" "1 1 0.7" "2 1 0.5" "3 1 0.5" "4 1 0.5" "2 2 0.5"; do
    set -- $cfg
    ./build/tmpc explicit --controller "$artifact" --out "$tmp/law.tmpcx" --report "$tmp/r.json" \
      --horizon "$1" --control-horizon "$2" --domain-fraction "$3" --time-limit 1200 >/dev/null
    /usr/bin/python3 - "$tmp/r.json" "$1" "$2" "$3" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]:<4} {sys.argv[3]:<4} {sys.argv[4]:<8} {r['regions']:<8} {str(r['complete']):<10} "
      f"{r['build_seconds']:<9.1f} {r['tree']['seconds']:<8.1f} {r['tree']['depth']:<10} {r['memory_bytes']/1024:<8.0f}")
PY
  done
} | tee "$out"
rm -rf "$tmp"
echo "results: $out"
