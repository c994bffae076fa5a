// CUDA device discovery, with every runtime call checked.
#include "device_info.hpp"

#include <cstdio>
#include <cstring>

#include <cuda_runtime.h>

namespace tmpc {
namespace cuda {

namespace {
int fail(cudaError_t e, const char* what, char* message, std::size_t len) {
  if (message != nullptr && len > 0) {
    std::snprintf(message, len, "%s: %s (%s)", what, cudaGetErrorString(e), cudaGetErrorName(e));
  }
  return -1;
}
}  // namespace

int query_devices(DeviceInfo* out, int max, char* message, std::size_t message_len) {
  int count = 0;
  cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) return fail(e, "cudaGetDeviceCount", message, message_len);
  int n = 0;
  for (int i = 0; i < count && n < max; ++i) {
    cudaDeviceProp p;
    e = cudaGetDeviceProperties(&p, i);
    if (e != cudaSuccess) return fail(e, "cudaGetDeviceProperties", message, message_len);
    DeviceInfo& d = out[n++];
    d.index = i;
    std::snprintf(d.name, sizeof(d.name), "%s", p.name);
    d.major = p.major;
    d.minor = p.minor;
    d.global_memory = p.totalGlobalMem;
    d.multiprocessors = p.multiProcessorCount;
    d.integrated = p.integrated != 0;
  }
  if (message != nullptr && message_len > 0) message[0] = '\0';
  return n;
}

int runtime_version() { return CUDART_VERSION; }

}  // namespace cuda
}  // namespace tmpc
