#!/usr/bin/env bash
# Install tmpc's controller as a systemd service (scripts/deploy/tmpc-controller.service.in).
# Usage: scripts/install_service.sh --controller FILE.tmpc --port DEV [--scenario FILE]
#          [--solver auto] [--rt-priority 80] [--cpu N] [--telemetry-dir DIR] [--user USER]
#          [--bin PATH] [--root DIR] [--no-enable]
# --root DIR writes the unit under DIR (a staging tree, no systemctl); otherwise it goes
# to /etc/systemd/system and is enabled and started (unless --no-enable).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
controller="" port="" scenario="" solver="auto" priority=80 cpu=-1 telemetry_dir="/var/log/tmpc" user="root"
bin="" root="" enable=1
die() { echo "install_service: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --controller) controller="$2"; shift 2 ;;
    --port) port="$2"; shift 2 ;;
    --scenario) scenario="$2"; shift 2 ;;
    --solver) solver="$2"; shift 2 ;;
    --rt-priority) priority="$2"; shift 2 ;;
    --cpu) cpu="$2"; shift 2 ;;
    --telemetry-dir) telemetry_dir="$2"; shift 2 ;;
    --user) user="$2"; shift 2 ;;
    --bin) bin="$2"; shift 2 ;;
    --root) root="$2"; shift 2 ;;
    --no-enable) enable=0; shift ;;
    -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
    *) die "unknown option '$1' (see --help)" ;;
  esac
done
[ -n "$controller" ] || die "--controller FILE.tmpc is required"
[ -n "$port" ] || die "--port DEV is required"
[[ "$priority" =~ ^[0-9]+$ ]] && [ "$priority" -ge 1 ] && [ "$priority" -le 99 ] || die "--rt-priority must be 1..99, got '$priority'"
[[ "$cpu" =~ ^-?[0-9]+$ ]] || die "--cpu must be a CPU number, got '$cpu'"
[ -f "$controller" ] || die "$controller: no such controller artifact"
controller="$(cd "$(dirname "$controller")" && pwd)/$(basename "$controller")"
if [ -z "$scenario" ]; then scenario="$here/../config/scenarios/thesis_helix.yaml"; fi
[ -f "$scenario" ] || die "$scenario: no such scenario"
scenario="$(cd "$(dirname "$scenario")" && pwd)/$(basename "$scenario")"
if [ -z "$bin" ]; then bin="$(command -v tmpc || true)"; [ -n "$bin" ] || bin="$here/../build/tmpc"; fi
[ -x "$bin" ] || die "$bin: no tmpc executable (build it, or give --bin)"
bin="$(cd "$(dirname "$bin")" && pwd)/$(basename "$bin")"
cpu_arg="" cpu_affinity=""
if [ "$cpu" -ge 0 ]; then cpu_arg=" --cpu $cpu"; cpu_affinity="CPUAffinity=$cpu"; fi
unit_dir="$root/etc/systemd/system"
mkdir -p "$unit_dir" "$root$telemetry_dir"
unit="$unit_dir/tmpc-controller.service"
sed -e "s|@BIN@|$bin|g" -e "s|@ARTIFACT@|$controller|g" -e "s|@PORT@|$port|g" -e "s|@SCENARIO@|$scenario|g" \
    -e "s|@SOLVER@|$solver|g" -e "s|@PRIORITY@|$priority|g" -e "s|@CPU_ARG@|$cpu_arg|g" \
    -e "s|@CPU_AFFINITY@|$cpu_affinity|g" -e "s|@TELEMETRY_DIR@|$telemetry_dir|g" -e "s|@USER@|$user|g" \
    "$here/deploy/tmpc-controller.service.in" > "$unit"
echo "install_service: wrote $unit"
if [ -z "$root" ] && [ "$enable" -eq 1 ]; then
  command -v systemctl >/dev/null 2>&1 || die "no systemctl here: the unit is written, start it by hand"
  systemctl daemon-reload
  systemctl enable --now tmpc-controller.service
  echo "install_service: enabled and started; journalctl -u tmpc-controller -f follows it"
fi
