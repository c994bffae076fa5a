#!/usr/bin/env bash
# Bundle the CUDA test and benchmark binaries, the tmpc CLI and the default controller
# (config/tiltrotor.yaml designed into tiltrotor.tmpc) with the Debian libraries they
# need into .gpu_bundle/ (ignored by git), for a GPU machine that has the CUDA toolkit
# but not tmpc's dependencies. There, from a copy of this tree:
#   TMPC_SOURCE_DIR=$PWD TMPC_TEST_ARTIFACTS=$PWD/.gpu_bundle TMPC_ARTIFACT=.gpu_bundle/tiltrotor.tmpc \
#     LD_LIBRARY_PATH=$PWD/.gpu_bundle/lib:/usr/local/cuda/lib64 \
#     RESULTS=$OUT scripts/gpu_checks_from_binaries.sh .gpu_bundle
# CUDA's own libraries (cuBLAS) are not bundled: the machine's toolkit must provide the
# same major version as this build's (ldd .gpu_bundle/tests/test_cuda says which). Nor
# are the C and C++ runtimes: the machine's own are used (newer ones read older binaries).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh -DTMPC_WITH_CUDA=ON >/dev/null
rm -rf .gpu_bundle
mkdir -p .gpu_bundle/tests .gpu_bundle/bench .gpu_bundle/lib
cp build/tests/test_cuda .gpu_bundle/tests/
cp build/bench/tmpc_bench_cuda .gpu_bundle/bench/
cp build/tmpc .gpu_bundle/
for b in build/tests/test_cuda build/bench/tmpc_bench_cuda build/tmpc; do
  ldd "$b" | awk '/=> \//{print $3}' | while read -r lib; do
    case "$lib" in
      */libc.so*|*/libm.so*|*/libpthread.so*|*/libdl.so*|*/librt.so*|*/ld-linux*|*/libstdc++.so*|*/libgcc_s.so*) ;;
      /usr/local/cuda*|*/libcuda.so*|*/libcublas*) ;;
      *) cp -L "$lib" .gpu_bundle/lib/ ;;
    esac
  done
done
build/tmpc design --config config/tiltrotor.yaml --out .gpu_bundle/tiltrotor.tmpc >/dev/null
# The tests' quick design (cached in build/tests by any test that uses it), loaded there
# through TMPC_TEST_ARTIFACTS=.gpu_bundle: the build tree's cache is not on that machine.
ls build/tests/quick@*.tmpc >/dev/null 2>&1 || build/tests/test_gpu_kernel --gtest_brief=1 >/dev/null
cp "$(ls -t build/tests/quick@*.tmpc | head -1)" .gpu_bundle/quick.tmpc
du -sh .gpu_bundle
