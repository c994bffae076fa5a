// Telemetry writer thread (see telemetry.hpp).
#include "tmpc/runtime/telemetry.hpp"

#include <chrono>
#include <stdexcept>

#include "tmpc/io/protocol.hpp"

namespace tmpc {

TelemetryWriter::TelemetryWriter(const std::string& path, TelemetryLayout layout, std::size_t capacity)
    : layout_(std::move(layout)), ring_(capacity) {
  const int n = static_cast<int>(layout_.state_names.size()), m = static_cast<int>(layout_.input_names.size());
  if (n > kMaxStates || m > kMaxInputs || layout_.measured > n || layout_.disturbances > 3) {
    throw std::invalid_argument("telemetry: " + std::to_string(n) + " states and " + std::to_string(m) +
                                " inputs exceed a record");
  }
  f_ = std::fopen(path.c_str(), "w");
  if (f_ == nullptr) throw std::runtime_error(path + ": cannot open the telemetry file for writing");
  if (!layout_.comment.empty()) std::fprintf(f_, "# %s\n", layout_.comment.c_str());
  std::fprintf(f_, "period,t");
  for (const std::string& s : layout_.state_names) std::fprintf(f_, ",e_%s", s.c_str());
  for (int i = 0; i < layout_.measured; ++i) std::fprintf(f_, ",r_%s", layout_.state_names[static_cast<std::size_t>(i)].c_str());
  for (const std::string& s : layout_.state_names) std::fprintf(f_, ",xbar_%s", s.c_str());
  for (const std::string& s : layout_.input_names) std::fprintf(f_, ",ubar_%s", s.c_str());
  for (const std::string& s : layout_.input_names) std::fprintf(f_, ",u_%s", s.c_str());
  std::fprintf(f_, ",status,iterations,solve_us,wake_latency_us,period_us,fallback,clipped,in_tube,safe_command");
  static const char* const dn[3] = {"dhat_x", "dhat_y", "dhat_z"};
  for (int i = 0; i < layout_.disturbances; ++i) std::fprintf(f_, ",%s", dn[i]);
  for (std::size_t i = 0; i < io::kRejectReasons; ++i) std::fprintf(f_, ",rejected_%s", io::to_string(static_cast<io::Reject>(i)));
  std::fprintf(f_, ",peer_session,restart,softened,slack_max,filtered,noise_level,gated,step\n");
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
  const int n = static_cast<int>(layout_.state_names.size()), m = static_cast<int>(layout_.input_names.size());
  std::fprintf(f_, "%llu,%.6f", static_cast<unsigned long long>(r.period), r.t);
  for (int i = 0; i < n; ++i) std::fprintf(f_, ",%.9g", r.x[i]);
  for (int i = 0; i < layout_.measured; ++i) std::fprintf(f_, ",%.9g", r.ref[i]);
  for (int i = 0; i < n; ++i) std::fprintf(f_, ",%.9g", r.x_bar[i]);
  for (int i = 0; i < m; ++i) std::fprintf(f_, ",%.9g", r.u_bar[i]);
  for (int i = 0; i < m; ++i) std::fprintf(f_, ",%.9g", r.u[i]);
  std::fprintf(f_, ",%d,%d,%.3f,%.3f,%.3f,%u,%u,%u,%u", r.status, r.iterations, r.solve_us, r.wake_latency_us,
               r.period_us, r.fallback, r.clipped, r.in_tube, r.safe_command);
  for (int i = 0; i < layout_.disturbances; ++i) std::fprintf(f_, ",%.6g", r.d_hat[i]);
  for (std::int32_t c : r.link_rejects) std::fprintf(f_, ",%d", c);
  std::fprintf(f_, ",%u,%u,%u,%.6g,%u,%.4g,%u,%u\n", r.peer_session, r.restart, r.softened, r.slack_max, r.filtered,
               r.noise_level, r.gated, r.step);
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
