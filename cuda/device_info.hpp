// CUDA device discovery (C++14, no CUDA headers): which GPUs the runtime can use.
// Every CUDA call is checked; a failure is a status with the CUDA message, never
// an abort, so a machine without a GPU (or without a driver) just reports none.
#pragma once

#include <cstddef>

namespace tmpc {
namespace cuda {

struct DeviceInfo {
  int index;
  char name[256];
  int major;  // compute capability
  int minor;
  std::size_t global_memory;  // bytes
  int multiprocessors;
  bool integrated;  // Jetson: shares memory with the CPU (zero-copy capable)
};

/// Fill up to `max` entries; return the number found, or -1 on a CUDA error with
/// the reason in `message` (e.g. "no CUDA-capable device is detected").
int query_devices(DeviceInfo* out, int max, char* message, std::size_t message_len);

/// CUDA runtime version the code was built against (e.g. 13000).
int runtime_version();

}  // namespace cuda
}  // namespace tmpc
