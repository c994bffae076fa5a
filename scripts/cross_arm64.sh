#!/usr/bin/env bash
# The CPU path for arm64 (Jetson Orin, TX2), cross-built here and tested under user-mode
# emulation (qemu-aarch64); CI runs it (scripts/ci_variants.sh arm64):
#   1. Debian's arm64 cross toolchain, qemu-user and the arm64 (multiarch) packages of
#      our libraries; libyaml-cpp-dev, which cannot be installed beside the host's, is
#      unpacked into build-arm64-sysroot/ (cmake/aarch64-linux-gnu.cmake looks there);
#   2. build-arm64/: the libraries, `tmpc` and the test executables named in
#      TMPC_ARM64_TESTS, for TMPC_TARGET_CPU (default cortex-a78ae, the Orin);
#   3. those tests under qemu, with the host's designs of the test artifacts
#      (TMPC_TEST_ARTIFACTS: a design under emulation takes many minutes), and 10 s of
#      the thesis mission flown by the arm64 `tmpc` and by the host's, default solver:
#      the same numbers.
# TMPC_ARM64_TESTS entries are EXECUTABLE or EXECUTABLE:GTEST_FILTER. The default list
# runs the model, sets, qp and io tests whole, the solvers tests of a second or less on
# the host (emulation is 20-50 times slower: the whole of test_solvers takes more than
# 20 min under qemu here) and the runtime tests but one (below).
# The synthesis, explicit and metrics tests (designs) and CUDA are not run under
# emulation.
# Measured on a 2-core VM: see the README's "arm64, cross-built and emulated".
# Usage: [TMPC_ARM64_TESTS="test_model test_solvers:ActiveSet.* ..."] scripts/cross_arm64.sh [CPU]
#        (after scripts/build.sh: the host's build designs the test artifacts)
set -euo pipefail
cd "$(dirname "$0")/.."
cpu="${1:-cortex-a78ae}"
t0=$(date +%s)
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
if ! dpkg --print-foreign-architectures | grep -qx arm64; then
  $SUDO dpkg --add-architecture arm64
  $SUDO apt-get update -qq
fi
# --no-remove: never trade a host package for an arm64 one.
$SUDO apt-get install -y -qq --no-install-recommends --no-remove crossbuild-essential-arm64 qemu-user \
  libyaml-cpp0.7:arm64 libspdlog-dev:arm64 libfmt-dev:arm64 libgtest-dev:arm64 libgmock-dev:arm64 \
  libsdp-dev:arm64 coinor-libclp-dev:arm64 libc6:arm64 libstdc++6:arm64 libgomp1:arm64 >/dev/null
sysroot=build-arm64-sysroot
if [ ! -f "$sysroot/usr/lib/aarch64-linux-gnu/cmake/yaml-cpp/yaml-cpp-config.cmake" ]; then
  tmp=$(mktemp -d)
  (cd "$tmp" && apt-get download libyaml-cpp-dev:arm64 libyaml-cpp0.7:arm64 >/dev/null)
  for deb in "$tmp"/*.deb; do dpkg -x "$deb" "$sysroot"; done
  rm -rf "$tmp"
fi
echo "=== arm64: packages ready in $(( $(date +%s) - t0 )) s"

generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
# ccache keys on the compiler too: the cross objects never mix with the host's.
launcher=()
command -v ccache >/dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-arm64 "${generator[@]}" "${launcher[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake -DTMPC_TARGET_CPU="$cpu" \
  -DTMPC_WITH_CUDA=OFF -DTMPC_WITH_MUJOCO=OFF -DTMPC_BUILD_BENCH=OFF >/dev/null
# The solvers tests of a second or less on the host: the exact ADMM, the active-set's
# certificate, screen and infeasibility tests, the Schur active set, the softened QP.
: "${TMPC_ARM64_SOLVERS_FILTER:=Solvers.ExactAdmm*:Solvers.CrashStart*:Solvers.WarmStartBeatsCold*:Solvers.RandomSmallMpcQps:SchurActiveSet.*:ActiveSet.RowsWithin*:ActiveSet.RedundantRowsOfAHandMadeQp:ActiveSet.CertifiesInfeasibility*:SoftConstraints.AnInfeasibleQpViolatesLeast*:SoftConstraints.ThePenaltyIsExactWhereTheHardQpIsFeasible}"
# The runtime tests but the envelope and force-envelope checks of the shipped
# scenarios (11 s and 3 s on the host, minutes under emulation; the force envelope's
# hand-worked cases stay).
: "${TMPC_ARM64_RUNTIME_FILTER:=-Preflight.TheShippedTrajectories*:ForceEnvelope.TheShippedScenarios:ForceEnvelope.PastEvery*:ForceEnvelope.HalfTheGustSeeds*}"
default_tests="test_model test_sets test_qp test_io \
test_solvers:${TMPC_ARM64_SOLVERS_FILTER} test_runtime:${TMPC_ARM64_RUNTIME_FILTER}"
read -r -a tests <<< "${TMPC_ARM64_TESTS:-$default_tests}"
targets=()
for t in "${tests[@]}"; do targets+=("${t%%:*}"); done
cmake --build build-arm64 -j"$(nproc)" --target tmpc "${targets[@]}"
python3 -c 'import sys; sys.exit(open(sys.argv[1], "rb").read(20)[18:20] != b"\xb7\x00")' build-arm64/tmpc ||
  { echo "cross_arm64: build-arm64/tmpc is not an arm64 (ELF e_machine 183) executable" >&2; exit 1; }
echo "=== arm64: built for $cpu in $(( $(date +%s) - t0 )) s"

# The host's designs of the test fixtures (tests/synthesis/design_fixture.hpp).
[ -x build/tests/test_runtime ] || { echo "cross_arm64: run scripts/build.sh first (the host's designs)" >&2; exit 1; }
build/tests/test_runtime --gtest_filter='TubeController.TheKalmanFilterStartsFromItsPrior*:TubeController.OffsetFreeObserver*:TubeController.TheSwitchedObserver*' \
  --gtest_brief=1 >/dev/null
art=build-arm64/artifacts
mkdir -p "$art"
cp "$(ls -t build/tests/quick@*.tmpc | head -1)" "$art/quick.tmpc"
cp "$(ls -t build/tests/noisy@*.tmpc | head -1)" "$art/noisy.tmpc"

# The executables run on the multiarch arm64 runtime (libc6:arm64 and friends in
# /lib/aarch64-linux-gnu, as on a board), not on the cross toolchain's own copy in
# /usr/aarch64-linux-gnu: under qemu-user 7.2 that copy's pthread_create never returns
# (a three-line C program hangs; the multiarch libc runs the same binary's threads).
qemu=(qemu-aarch64)
failed=0
# Each executable in as many gtest shards as there are cores, run at once (qemu-user
# emulates one thread on one core; the tests are independent: ctest runs them in
# parallel on the host).
shards=$(nproc)
for entry in "${tests[@]}"; do
  t="${entry%%:*}"
  filter=()
  [ "$t" != "$entry" ] && filter=(--gtest_filter="${entry#*:}")
  s=$(date +%s)
  pids=()
  for ((i = 0; i < shards; i++)); do
    GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i TMPC_TEST_ARTIFACTS="$PWD/$art" timeout 900 "${qemu[@]}" \
      "build-arm64/tests/$t" --gtest_brief=1 "${filter[@]}" > "build-arm64/$t.$i.log" 2>&1 &
    pids+=($!)
  done
  ok=1
  for pid in "${pids[@]}"; do wait "$pid" || ok=0; done
  ran=0
  for ((i = 0; i < shards; i++)); do
    n=$(grep -o '[0-9]* tests\? from' "build-arm64/$t.$i.log" | tail -1 | cut -d' ' -f1 || true)
    ran=$((ran + ${n:-0}))
  done
  if [ "$ok" = 1 ] && [ "$ran" -gt 0 ]; then
    echo "=== arm64: $t passed under qemu ($ran tests in $shards shards, $(( $(date +%s) - s )) s)"
  else
    echo "=== arm64: $t FAILED under qemu ($ran tests ran, $(( $(date +%s) - s )) s):"
    for ((i = 0; i < shards; i++)); do tail -30 "build-arm64/$t.$i.log"; done
    failed=1
  fi
done

# A short mission: the arm64 tmpc and the host's fly the same artifact.
"${qemu[@]}" build-arm64/tmpc simulate --controller "$art/quick.tmpc" --solver active-set --duration 10 \
  --out build-arm64/mission > build-arm64/mission.log 2>&1
build/tmpc simulate --controller "$art/quick.tmpc" --solver active-set --duration 10 --out build-arm64/mission-host >/dev/null 2>&1
python3 - build-arm64/mission/metrics.json build-arm64/mission-host/metrics.json <<'PY' || failed=1
import json, sys
a, h = (json.load(open(p)) for p in sys.argv[1:3])
worst = max(abs(a["rmse"][k] - h["rmse"][k]) / max(h["rmse"][k], 1e-12) for k in h["rmse"])
print(f"=== arm64: 10 s of the thesis mission: RMSE x {a['rmse']['x']:.6f} (host {h['rmse']['x']:.6f}), largest relative "
      f"RMSE difference {worst:.1e}, violations {a['state_constraint_violations']} (host {h['state_constraint_violations']}), "
      f"fallbacks {a['fallback_periods']}")
ok = (worst < 1e-3 and a["state_constraint_violations"] == h["state_constraint_violations"]
      and a["fallback_periods"] == h["fallback_periods"] and not a["diverged"])
sys.exit(0 if ok else "cross_arm64: the arm64 mission differs from the host's")
PY
echo "=== arm64: done in $(( $(date +%s) - t0 )) s"
exit $failed
