#!/usr/bin/env bash
# The build variants a user will build besides the default one, each configured, built
# and tested in its own build directory (after scripts/run_tests.sh has tested the
# default build with every test):
#   asan      TMPC_SANITIZE=ON TMPC_WITH_CUDA=OFF: ASan + UBSan over every CPU test but
#             the labels `slow` (the 80 s missions) and `fuzz` (the fuzz targets are
#             built by clang with ASan + UBSan whatever the options, and ran in the
#             default build), the three-gain comparisons of test_design_gains
#             (CSDP's SDPs at every LPV vertex) and the command-line checks that
#             design through `tmpc design` (cli.batch, cli.preflight,
#             cli.design_inspect_export, cli.best-case, cli.robustness-sweep: 269 s
#             under ASan, measured once): minutes each under ASan, their design code
#             runs under ASan in test_synthesis, their solves and checks in the unit
#             tests; and four checks that repeat code the other tests run under ASan
#             over every shipped file or QP set, most of their time in CLP's LPs or
#             Python (solvers.cvxopt_oracle 208 s, Preflight.TheShippedTrajectories...
#             143 s, ForceEnvelope.HalfTheGustSeeds... 96 s, ForceEnvelope.TheShipped-
#             Scenarios 90 s under ASan, measured once; the other Preflight.* and
#             ForceEnvelope.* tests and Solvers.* run there); Solvers.FiveHundredCaseStudyQps
#             (101 s; the offset-free comparison of the same four solvers runs) and, in
#             test_synthesis (one ctest test: GTEST_FILTER), the case study's RPI tube,
#             thesis-form LMI gain and sampled-uncertainty design (134, 95 and 71 s of its
#             351 s under ASan, measured once; the small-system RPI, LMI and design tests
#             run the same code there). Sampled checks run a tenth of their samples
#             (tests/model/test_support.hpp). It is also the build without CUDA (a
#             machine without nvcc): it builds and passes without it.
#   nomujoco  TMPC_WITH_MUJOCO=OFF (a Jetson image without MuJoCo): builds, and runs
#             the tests of what the option changes: the command line (label `cli`:
#             `plant`, `openloop`, `crosscheck` refuse the MuJoCo plant, saying why)
#             and the plant selection (`Plant*`, `Scenario*`). Not the command-line
#             checks that design and fly the default (Euler-Lagrange) plant for minutes
#             (batch, preflight, design_inspect_export, best-case, best-case-gust,
#             robustness-sweep: 490 s of the variant's 546 s of tests, measured once):
#             the option changes nothing they run, and the default build runs them.
#   arm64     scripts/cross_arm64.sh: the CPU path cross-built for the Orin (Debian's
#             arm64 toolchain and multiarch packages), its model, sets, qp and io tests
#             and a named subset of the solvers and runtime tests under qemu-aarch64,
#             and 10 s of the thesis mission flown by the arm64 tmpc and the host's.
#             Needs the default build (build/: the host's designs of the test artifacts).
#   nocuda    TMPC_WITH_CUDA=OFF without sanitizers (not in CI: asan covers it).
# ccache shares the object files the variants have in common with the default build.
# Usage: scripts/ci_variants.sh [VARIANT...]   (default: asan nomujoco arm64)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
variants=("$@")
[ ${#variants[@]} -eq 0 ] && variants=(asan nomujoco arm64)
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_CUDA_COMPILER_LAUNCHER=ccache)
for v in "${variants[@]}"; do
  t0=$(date +%s)
  if [ "$v" = arm64 ]; then
    echo "=== variant arm64: scripts/cross_arm64.sh"
    scripts/cross_arm64.sh
    echo "=== variant arm64: built and tested in $(( $(date +%s) - t0 )) s"
    continue
  fi
  gtest_env=()
  case "$v" in
    asan) opts=(-DTMPC_SANITIZE=ON -DTMPC_WITH_CUDA=OFF -DTMPC_BUILD_BENCH=OFF); ctest_args=(-LE "slow|fuzz" -E "^(DesignGains\.|cli\.(batch|preflight|design_inspect_export|best-case|best-case-gust|robustness-sweep)$|solvers\.cvxopt_oracle$|Preflight\.TheShippedTrajectoriesAreInsideTheDefaultEnvelope$|ForceEnvelope\.(HalfTheGustSeedsPushTheStaticTiltOutOfTheBox|TheShippedScenarios)$|Solvers\.FiveHundredCaseStudyQps$)")
          gtest_env=(GTEST_FILTER="-Rpi.CaseStudyDefaultTubePassesBothIndependentChecks:LmiGain.CaseStudyThesisFormAtTheNominalModel:Design.SampledUncertaintyIsReportedAsSuch") ;;
    nomujoco) opts=(-DTMPC_WITH_MUJOCO=OFF -DTMPC_BUILD_BENCH=OFF); ctest_args=(-LE "slow|fuzz" -R "^(cli\.|[A-Za-z]*Plant|Scenario)" -E "^cli\.(batch|preflight|design_inspect_export|best-case|best-case-gust|robustness-sweep)$") ;;
    nocuda) opts=(-DTMPC_WITH_CUDA=OFF); ctest_args=(-LE "slow|fuzz") ;;
    *) echo "ci_variants: unknown variant '$v' (asan, nomujoco, arm64, nocuda)" >&2; exit 2 ;;
  esac
  echo "=== variant $v: ${opts[*]}"
  cmake -S . -B "build-$v" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${opts[@]}" >/dev/null
  cmake --build "build-$v" -j"$(nproc)"
  (cd "build-$v" && env ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 "${gtest_env[@]}" \
    ctest --output-on-failure -j"$(nproc)" "${ctest_args[@]}")
  echo "=== variant $v: built and tested in $(( $(date +%s) - t0 )) s"
done
