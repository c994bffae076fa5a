#!/usr/bin/env bash
# Install what is missing, build, and run every test (ctest). CUDA tests skip,
# saying why, when no GPU is present.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
cd build
ctest --output-on-failure -j"$(nproc)"
