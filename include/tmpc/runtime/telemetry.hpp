// Telemetry of the real-time loop: one fixed-size record a period goes through a
// single-producer single-consumer lock-free ring to a writer thread that appends CSV
// lines. The real-time side never blocks, locks or allocates; if the ring is ever full
// the record is counted as dropped (and reported), never silently lost.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "tmpc/model/state_layout.hpp"

namespace tmpc {

/// One period of the loop, sized for the largest design (kMaxStates, kMaxInputs); the
/// writer prints the first n (states), p (measured) and m (inputs) entries.
struct TelemetryRecord {
  std::uint64_t period = 0;
  double t = 0.0;                      ///< s since the loop started
  double x[kMaxStates] = {};           ///< error state x_tilde (physical)
  double ref[kMaxStates] = {};         ///< reference of the measured states x_r
  double x_bar[kMaxStates] = {};       ///< nominal state (normalized)
  double u_bar[kMaxInputs] = {};       ///< u_bar(0), physical error units
  double u[kMaxInputs] = {};           ///< applied input (physical)
  std::int32_t status = 0;     ///< SolveStatus
  std::int32_t iterations = 0;
  double solve_us = 0.0;
  double wake_latency_us = 0.0;  ///< actual minus planned wake-up
  double period_us = 0.0;        ///< since the previous wake-up (jitter = period_us - T)
  std::uint8_t fallback = 0, clipped = 0, in_tube = 1, safe_command = 0;
  double d_hat[3] = {};          ///< offset-free: the estimated disturbance (tiltrotor: force on the load, N)
  std::int32_t link_rejects[9] = {};  ///< state frames rejected so far, by io::Reject
  std::uint32_t peer_session = 0;     ///< the plant's session on the link
  std::uint8_t restart = 0;           ///< the law restarted from this period's state
  std::uint8_t softened = 0;          ///< the softened QP's input (the hard QP was infeasible)
  double slack_max = 0.0;             ///< its largest slack (physical units of its state)
  std::uint8_t filtered = 0;          ///< the Kalman filter's estimate flew (switched observer: else the measurement)
  double noise_level = 0.0;           ///< the noise monitor's level (fraction of the design's)
  std::uint8_t gated = 0;             ///< measured rows the filter's innovation gate replaced (glitches)
  std::uint8_t step = 0;              ///< a disturbance step was read in the filter's innovations (its gains re-opened):
                                      ///< 1, or 2 where it re-opened the lift too (step_reopens_lift); 3: a step
                                      ///< older than the detection window, left to the steady gain (late_step_keeps_gain)
};

/// The columns of a telemetry file: the artifact's state and input names.
struct TelemetryLayout {
  std::vector<std::string> state_names, input_names;
  int measured = 0;
  int disturbances = 0;  ///< d_hat entries (at most 3)
  std::string comment;   ///< non-empty: a first line "# comment" (e.g. why this solver flies)
};

/// Lock-free ring for one producer and one consumer; capacity rounded up to a power of 2.
template <class T>
class SpscRing {
 public:
  explicit SpscRing(std::size_t capacity) {
    std::size_t c = 2;
    while (c < capacity) c <<= 1;
    buf_.resize(c);
    mask_ = c - 1;
  }
  bool push(const T& v) {
    const std::size_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) > mask_) return false;  // full
    buf_[h & mask_] = v;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }
  bool pop(T& v) {
    const std::size_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return false;  // empty
    v = buf_[t & mask_];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }
  std::size_t capacity() const { return mask_ + 1; }

 private:
  std::vector<T> buf_;
  std::size_t mask_ = 0;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

class TelemetryWriter {
 public:
  /// Opens `path` (CSV with a header of `layout`'s names) and starts the writer thread.
  /// Throws on open failure or a layout beyond the record's sizes.
  TelemetryWriter(const std::string& path, TelemetryLayout layout, std::size_t capacity = 1 << 12);
  ~TelemetryWriter();  ///< drains the ring, flushes, closes
  TelemetryWriter(const TelemetryWriter&) = delete;
  TelemetryWriter& operator=(const TelemetryWriter&) = delete;
  /// Real-time side: never blocks. False (and counted) when the ring is full.
  bool push(const TelemetryRecord& r);
  std::uint64_t pushed() const { return pushed_.load(std::memory_order_relaxed); }
  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_.load(std::memory_order_acquire); }
  /// Writer-side pause (tests: a stalled disk).
  void pause_writer(bool p) { paused_.store(p, std::memory_order_release); }

 private:
  void run();
  void write(const TelemetryRecord& r);
  TelemetryLayout layout_;
  std::FILE* f_ = nullptr;
  SpscRing<TelemetryRecord> ring_;
  std::atomic<std::uint64_t> pushed_{0}, dropped_{0}, written_{0};
  std::atomic<bool> stop_{false}, paused_{false};
  std::thread thread_;
};

}  // namespace tmpc
