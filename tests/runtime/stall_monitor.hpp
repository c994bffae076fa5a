// An independent measure of host stalls for the wall-clock tests: a thread that sleeps
// 1 ms at a time and records how late it woke. When it saw no stall, a late loop is
// the loop's own fault (the test fails); when it did, the machine was not scheduling
// threads (a VM's steal time) and timing claims cannot be judged from that run.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

namespace tmpc::test {

/// Wall-clock seconds per mission second for the hardware-in-the-loop tests: 1, or 6
/// in a sanitizer build, whose 5 to 20 times slower code cannot keep a 12 ms period
/// (the loops' time_scale stretches the period and the deadline; the logic, the link
/// and the mission are the same).
#if defined(__SANITIZE_ADDRESS__)
constexpr double kWallTimeScale = 6.0;
#else
constexpr double kWallTimeScale = 1.0;
#endif

class StallMonitor {
 public:
  StallMonitor() : thread_([this] { run(); }) {}
  ~StallMonitor() { stop(); }
  StallMonitor(const StallMonitor&) = delete;
  StallMonitor& operator=(const StallMonitor&) = delete;
  /// Stops the sleeper; returns the worst oversleep seen, ms.
  double stop() {
    if (thread_.joinable()) {
      stop_.store(true);
      thread_.join();
    }
    return worst_ms_;
  }
  double worst_ms() const { return worst_ms_; }

 private:
  void run() {
    using clock = std::chrono::steady_clock;
    while (!stop_.load()) {
      const auto planned = clock::now() + std::chrono::milliseconds(1);
      std::this_thread::sleep_until(planned);
      const double late = std::chrono::duration<double, std::milli>(clock::now() - planned).count();
      worst_ms_ = std::max(worst_ms_, late);
    }
  }
  std::atomic<bool> stop_{false};
  double worst_ms_ = 0.0;
  std::thread thread_;
};

}  // namespace tmpc::test
