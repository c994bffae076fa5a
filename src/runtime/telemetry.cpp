// Telemetry writer thread (see telemetry.hpp).
#include "tmpc/runtime/telemetry.hpp"

#include <chrono>
#include <stdexcept>

#include "tmpc/io/protocol.hpp"
#include "tmpc/model/kinematic_tree.hpp"

namespace tmpc {

TelemetryWriter::TelemetryWriter(const std::string& path, std::size_t capacity) : ring_(capacity) {
  f_ = std::fopen(path.c_str(), "w");
  if (f_ == nullptr) throw std::runtime_error(path + ": cannot open the telemetry file for writing");
  std::fprintf(f_, "period,t");
  for (int i = 0; i < 24; ++i) std::fprintf(f_, ",x%d", i);
  for (const char* n : kCoordNames) std::fprintf(f_, ",r_%s", n);
  for (int i = 0; i < 24; ++i) std::fprintf(f_, ",xbar%d", i);
  std::fprintf(f_, ",ubar_f_r,ubar_f_l,ubar_tau_r,ubar_tau_l,u_f_r,u_f_l,u_tau_r,u_tau_l,status,iterations,solve_us,"
                   "wake_latency_us,period_us,fallback,clipped,in_tube,safe_command,dhat_x,dhat_y,dhat_z");
  for (std::size_t i = 0; i < io::kRejectReasons; ++i) std::fprintf(f_, ",rejected_%s", io::to_string(static_cast<io::Reject>(i)));
  std::fprintf(f_, ",peer_session,restart\n");
  thread_ = std::thread([this] { run(); });
}

TelemetryWriter::~TelemetryWriter() {
  paused_.store(false, std::memory_order_release);
  stop_.store(true, std::memory_order_release);
  thread_.join();
  std::fclose(f_);
}

bool TelemetryWriter::push(const TelemetryRecord& r) {
  pushed_.fetch_add(1, std::memory_order_relaxed);
  if (ring_.push(r)) return true;
  dropped_.fetch_add(1, std::memory_order_relaxed);
  return false;
}

void TelemetryWriter::write(const TelemetryRecord& r) {
  std::fprintf(f_, "%llu,%.6f", static_cast<unsigned long long>(r.period), r.t);
  for (double v : r.x) std::fprintf(f_, ",%.9g", v);
  for (double v : r.ref) std::fprintf(f_, ",%.9g", v);
  for (double v : r.x_bar) std::fprintf(f_, ",%.9g", v);
  for (double v : r.u_bar) std::fprintf(f_, ",%.9g", v);
  for (double v : r.u) std::fprintf(f_, ",%.9g", v);
  std::fprintf(f_, ",%d,%d,%.3f,%.3f,%.3f,%u,%u,%u,%u,%.6g,%.6g,%.6g", r.status, r.iterations, r.solve_us,
               r.wake_latency_us, r.period_us, r.fallback, r.clipped, r.in_tube, r.safe_command, r.d_hat[0], r.d_hat[1],
               r.d_hat[2]);
  for (std::int32_t c : r.link_rejects) std::fprintf(f_, ",%d", c);
  std::fprintf(f_, ",%u,%u\n", r.peer_session, r.restart);
}

void TelemetryWriter::run() {
  TelemetryRecord r;
  for (;;) {
    const bool stopping = stop_.load(std::memory_order_acquire);
    if (!paused_.load(std::memory_order_acquire)) {
      bool any = false;
      while (ring_.pop(r)) {
        write(r);
        written_.fetch_add(1, std::memory_order_release);
        any = true;
      }
      if (any) std::fflush(f_);
      if (stopping) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

}  // namespace tmpc
