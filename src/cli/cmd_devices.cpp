// `tmpc devices`: the accelerators this build can use (CUDA), or why there are none.
#include <cstdio>

#include "commands.hpp"
#ifdef TMPC_HAVE_CUDA
#include "device_info.hpp"
#endif

namespace tmpc::cli {

namespace {
int run_devices() {
#ifdef TMPC_HAVE_CUDA
  cuda::DeviceInfo devs[16];
  char msg[512];
  const int n = cuda::query_devices(devs, 16, msg, sizeof msg);
  std::printf("built with CUDA runtime %d\n", cuda::runtime_version());
  if (n < 0) {
    std::printf("no usable CUDA device: %s\n", msg);
    return 0;
  }
  if (n == 0) std::printf("no CUDA device found\n");
  for (int i = 0; i < n; ++i) {
    std::printf("device %d: %s, sm_%d%d, %d SMs, %.1f GiB%s\n", devs[i].index, devs[i].name, devs[i].major,
                devs[i].minor, devs[i].multiprocessors, static_cast<double>(devs[i].global_memory) / (1 << 30),
                devs[i].integrated ? ", integrated (zero-copy)" : "");
  }
#else
  std::printf("built without CUDA (TMPC_WITH_CUDA=OFF or nvcc not found): CPU solvers only\n");
#endif
  return 0;
}
}  // namespace

void register_devices(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("devices", "List the CUDA devices this build can use");
  sub->callback([]() { run_devices(); });
}

}  // namespace tmpc::cli
