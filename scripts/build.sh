#!/usr/bin/env bash
# Configure and build tmpc in ./build (Release). CUDA is used when nvcc is found.
# Extra CMake arguments pass through, e.g. scripts/build.sh -DTMPC_WITH_CUDA=OFF
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
elif [ $# -gt 0 ]; then
  cmake -S . -B build "$@"
fi
cmake --build build -j"$(nproc)"
