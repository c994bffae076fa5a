// `tmpc devices`: the accelerators this build can use (CUDA), or why there are none.
#include <cstdio>

#include "commands.hpp"
#ifdef TMPC_HAVE_CUDA
#include "device_info.hpp"
#endif

namespace tmpc::cli {

std::vector<std::string> device_lines(bool* usable) {
  std::vector<std::string> out;
  if (usable != nullptr) *usable = false;
#ifdef TMPC_HAVE_CUDA
  cuda::DeviceInfo devs[16];
  char msg[512];
  const int n = cuda::query_devices(devs, 16, msg, sizeof msg);
  out.push_back("built with CUDA runtime " + std::to_string(cuda::runtime_version()));
  if (n < 0) {
    out.push_back(std::string("no usable CUDA device: ") + msg);
    return out;
  }
  if (n == 0) out.push_back("no CUDA device found");
  for (int i = 0; i < n; ++i) {
    char line[256];
    std::snprintf(line, sizeof line, "device %d: %s, sm_%d%d, %d SMs, %.1f GiB%s", devs[i].index, devs[i].name,
                  devs[i].major, devs[i].minor, devs[i].multiprocessors,
                  static_cast<double>(devs[i].global_memory) / (1 << 30), devs[i].integrated ? ", integrated (zero-copy)" : "");
    out.push_back(line);
  }
  if (usable != nullptr) *usable = n > 0;
#else
  out.push_back("built without CUDA (TMPC_WITH_CUDA=OFF or nvcc not found): CPU solvers only");
#endif
  return out;
}

void register_devices(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("devices", "List the CUDA devices this build can use");
  sub->callback([]() {
    for (const std::string& l : device_lines(nullptr)) std::printf("%s\n", l.c_str());
  });
}

}  // namespace tmpc::cli
