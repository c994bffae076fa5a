#!/usr/bin/env bash
# The main job: install what is missing, build, and run the default configuration.
# Now: the tiltrotor model pipeline (equilibrium, feedforward, linear error model).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
./build/tmpc model --config config/tiltrotor.yaml
