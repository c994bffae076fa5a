#!/usr/bin/env bash
# The build variants a user will build, each configured, built and tested in its own
# build directory (after scripts/run_tests.sh has tested the default build):
#   nomujoco  TMPC_WITH_MUJOCO=OFF  (a Jetson image without MuJoCo)
#   nocuda    TMPC_WITH_CUDA=OFF    (a machine without nvcc)
#   asan      TMPC_SANITIZE=ON      (ASan + UBSan over the CPU tests; label `slow`, the
#                                    80 s missions, left out)
# ccache shares the object files the variants have in common. Usage:
#   scripts/ci_variants.sh [VARIANT...]   (default: all three)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
variants=("$@")
[ ${#variants[@]} -eq 0 ] && variants=(nomujoco nocuda asan)
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
for v in "${variants[@]}"; do
  t0=$(date +%s)
  case "$v" in
    nomujoco) opts=(-DTMPC_WITH_MUJOCO=OFF); ctest_args=() ;;
    nocuda) opts=(-DTMPC_WITH_CUDA=OFF); ctest_args=() ;;
    asan) opts=(-DTMPC_SANITIZE=ON -DTMPC_WITH_CUDA=OFF -DTMPC_BUILD_BENCH=OFF); ctest_args=(-LE slow) ;;
    *) echo "ci_variants: unknown variant '$v' (nomujoco, nocuda, asan)" >&2; exit 2 ;;
  esac
  echo "=== variant $v: ${opts[*]}"
  cmake -S . -B "build-$v" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${opts[@]}" >/dev/null
  cmake --build "build-$v" -j"$(nproc)"
  (cd "build-$v" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure -j"$(nproc)" "${ctest_args[@]}")
  echo "=== variant $v: built and tested in $(( $(date +%s) - t0 )) s"
done
