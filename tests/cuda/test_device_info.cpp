// CUDA device discovery: reports devices or a reason, never crashes; skips the
// device checks (saying why) on a machine without a GPU.
#include <gtest/gtest.h>

#include "device_info.hpp"

namespace {

TEST(CudaDevices, QueryReportsDevicesOrAReason) {
  tmpc::cuda::DeviceInfo devs[8];
  char msg[512] = "unset";
  const int n = tmpc::cuda::query_devices(devs, 8, msg, sizeof msg);
  if (n < 0) {
    EXPECT_GT(std::string(msg).size(), 0u);
    GTEST_SKIP() << "no usable CUDA device: " << msg;
  }
  if (n == 0) GTEST_SKIP() << "no CUDA device on this machine";
  for (int i = 0; i < n; ++i) {
    EXPECT_GE(devs[i].major, 3) << devs[i].name;
    EXPECT_GT(devs[i].global_memory, 0u);
    EXPECT_GT(devs[i].multiprocessors, 0);
  }
  EXPECT_GE(tmpc::cuda::runtime_version(), 10000);
}

}  // namespace
