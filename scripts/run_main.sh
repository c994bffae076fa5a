#!/usr/bin/env bash
# The main job: install what is missing, build, design the default controller and fly
# the thesis mission in simulation (config/scenarios/thesis_helix.yaml: the 80 s helix,
# the thesis' 1 N steps at 20/40/60 s; the default solver, the Euler-Lagrange plant).
# Outputs under out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
mkdir -p out
./build/tmpc design --config config/tiltrotor.yaml --out out/tiltrotor.tmpc --report out/design_report.json
./build/tmpc simulate --controller out/tiltrotor.tmpc --scenario config/scenarios/thesis_helix.yaml --out out/helix
# The figures (thesis Figures 6.11-6.21 style): out/helix/plots/*.png.
/usr/bin/python3 scripts/plot_mission.py out/helix
