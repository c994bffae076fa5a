# Cross-compiling tmpc's CPU path for arm64 (Jetson Orin, TX2) on a Debian x86-64 host:
#   dpkg --add-architecture arm64 && apt-get update
#   apt-get install crossbuild-essential-arm64 qemu-user libyaml-cpp-dev:arm64 \
#     libspdlog-dev:arm64 libfmt-dev:arm64 libgtest-dev:arm64 libgmock-dev:arm64 \
#     libsdp-dev:arm64 coinor-libclp-dev:arm64        (scripts/cross_arm64.sh does this,
#     with libyaml-cpp-dev:arm64 unpacked into build-arm64-sysroot/ instead)
#   cmake -S . -B build-arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/aarch64-linux-gnu.cmake \
#     -DTMPC_WITH_CUDA=OFF -DTMPC_WITH_MUJOCO=OFF -DTMPC_TARGET_CPU=cortex-a78ae
# The multiarch packages put arm64 libraries in /usr/lib/aarch64-linux-gnu (headers are
# shared); ctest runs the tests through qemu-aarch64 (user-mode emulation).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_LIBRARY_ARCHITECTURE aarch64-linux-gnu)
# Programs (python3, the host's tools) from the host; libraries and packages for arm64 only.
# build-arm64-sysroot/: arm64 -dev packages that cannot be installed beside the host's
# (libyaml-cpp-dev), unpacked there by scripts/cross_arm64.sh.
get_filename_component(_tmpc_root "${CMAKE_CURRENT_LIST_DIR}/.." ABSOLUTE)
set(CMAKE_FIND_ROOT_PATH ${_tmpc_root}/build-arm64-sysroot /usr/aarch64-linux-gnu /usr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
find_program(TMPC_QEMU_AARCH64 qemu-aarch64)
if(TMPC_QEMU_AARCH64)
  # On the multiarch arm64 runtime (libc6:arm64, /lib/aarch64-linux-gnu), not the cross
  # toolchain's copy (-L /usr/aarch64-linux-gnu), whose pthread_create never returns
  # under qemu-user 7.2 (scripts/cross_arm64.sh).
  set(CMAKE_CROSSCOMPILING_EMULATOR ${TMPC_QEMU_AARCH64})
endif()
