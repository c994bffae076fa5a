#!/usr/bin/env bash
# Bundle the CUDA test and benchmark binaries with the Debian libraries they need into
# .gpu_bundle/ (ignored by git), for a GPU machine that has the CUDA toolkit but not
# tmpc's dependencies. There, from a copy of this tree:
#   TMPC_SOURCE_DIR=$PWD LD_LIBRARY_PATH=$PWD/.gpu_bundle/lib:/usr/local/cuda/lib64 \
#     RESULTS=$OUT scripts/gpu_checks_from_binaries.sh .gpu_bundle
# CUDA's own libraries (cuBLAS) are not bundled: the machine's toolkit must provide the
# same major version as this build's (ldd .gpu_bundle/tests/test_cuda says which).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DTMPC_WITH_CUDA=ON >/dev/null
rm -rf .gpu_bundle
mkdir -p .gpu_bundle/tests .gpu_bundle/bench .gpu_bundle/lib
cp build/tests/test_cuda .gpu_bundle/tests/
cp build/bench/tmpc_bench_cuda .gpu_bundle/bench/
for b in build/tests/test_cuda build/bench/tmpc_bench_cuda; do
  ldd "$b" | awk '/=> \//{print $3}' | while read -r lib; do
    case "$lib" in
      */libc.so*|*/libm.so*|*/libpthread.so*|*/libdl.so*|*/librt.so*|*/ld-linux*|/usr/local/cuda*|*/libcuda.so*) ;;
      *) cp -L "$lib" .gpu_bundle/lib/ ;;
    esac
  done
done
du -sh .gpu_bundle
