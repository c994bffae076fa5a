// The on-board loop (see controller_loop.hpp).
#include "tmpc/runtime/controller_loop.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/async_optimizer.hpp"
#include "tmpc/runtime/telemetry.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/runtime/tube_controller.hpp"

namespace tmpc {

ControllerLoopStats run_controller_loop(const ControllerArtifact& a, io::Transport& link,
                                        const ControllerLoopOptions& o, const std::atomic<bool>& stop) {
  // Everything that allocates happens here, before the loop.
  const Config cfg = load_config_from_string(a.config_text, "artifact");
  const TiltrotorModel model(cfg.vehicle);
  const HelixTrajectory traj(cfg.reference, model);
  SolverOptions so;
  so.eps_abs = so.eps_rel = cfg.solver.admm_epsilon;
  so.eta = cfg.solver.admm_eta;
  // A solve never outlives its period's deadline: past it the answer is useless, and
  // still running it would make the next period busy (the fallback twice).
  so.time_budget_us = o.deadline_fraction * a.sample_time * 1e6;
  const TubeControllerOptions law = tube_law_options(cfg, o.tube_law);
  TubeController ctrl(a, nullptr, law);
  AsyncOptimizer optimizer(make_controller_solver(o.solver, a, so, o.explicit_law, law.offset_free), ctrl.parameters());
  TrackingError err;
  ctrl.reset(err.value());
  std::unique_ptr<TelemetryWriter> telemetry;
  if (!o.telemetry_csv.empty()) telemetry = std::make_unique<TelemetryWriter>(o.telemetry_csv);
  io::Decoder decoder(io::FrameType::State);
  std::vector<std::uint8_t> out;
  out.reserve(128);
  std::uint8_t buf[1024];
  const double T = a.sample_time;
  const long max_periods = o.duration_s > 0.0 ? static_cast<long>(o.duration_s / T + 0.5) : -1;
  std::vector<double> latency, solve;
  latency.reserve(max_periods > 0 ? static_cast<std::size_t>(max_periods) : 1u << 20);
  solve.reserve(latency.capacity());
  ControllerLoopStats st;
  st.realtime = apply_realtime(o.realtime);
  PeriodicClock clock(T);
  io::StateFrame last{};
  bool have_state = false;
  long silent = 0;
  std::uint32_t seq = 0;
  TelemetryRecord rec;
  Eigen::Vector4d u_safe = a.u_eq;
  bool controlled_last = false;  // the previous period sent the law's input for a fresh state
  double last_state_time = -1.0;  // plant time of the state that input was computed from
  while (!stop.load(std::memory_order_relaxed) && (max_periods < 0 || st.periods + clock.skipped() < max_periods)) {
    const double lat = clock.wait();
    latency.push_back(lat);  // within the reserved capacity
    if (clock.last_period_us() > 0.0) {
      st.period_jitter_max_us = std::max(st.period_jitter_max_us, std::abs(clock.last_period_us() - T * 1e6));
    }
    bool fresh = false;
    for (;;) {
      const long n = link.read_some(buf, sizeof(buf));
      if (n <= 0) break;
      for (long i = 0; i < n; ++i) {
        if (decoder.push(buf[i])) {
          last = decoder.state();
          fresh = true;
        }
      }
    }
    silent = fresh ? 0 : silent + 1;
    have_state = have_state || fresh;
    ++st.periods;
    io::ControlFrame cf;
    cf.seq = ++seq;
    rec = TelemetryRecord{};
    rec.period = static_cast<std::uint64_t>(st.periods);
    rec.t = clock.elapsed_s();
    rec.wake_latency_us = lat;
    rec.period_us = clock.last_period_us();
    if (!have_state || silent > o.silent_periods) {
      // Safe command: the last feedforward with zero servo torques (hover before any state).
      cf.u = {u_safe(0), u_safe(1), 0.0, 0.0};
      cf.flags = io::ControlFrame::kSafe;
      ++st.safe_periods;
      rec.safe_command = 1;
      controlled_last = false;
    } else {
      ++st.states;
      const ReferencePoint r = traj.at(last.time);
      const Eigen::Vector4d u_r = feedforward(model, r);
      u_safe = u_r;
      State20 x;
      for (int i = 0; i < 20; ++i) x(i) = last.x[static_cast<std::size_t>(i)];
      const Eigen::VectorXd& xt = err.update(x, r);
      // The observer uses a residual only across one period of the law's own input.
      // ... and only when the plant moved by one period since that state (a stall of
      // either side makes the residual span several periods under inputs it did not
      // see: a wrong force estimate).
      const bool one_period = std::abs(last.time - last_state_time - T) < 0.5 * T;
      const std::uint64_t ticket = optimizer.start(ctrl.prepare(xt, fresh && controlled_last && one_period));
      controlled_last = fresh;
      last_state_time = last.time;
      // Deadline inside the period.
      const timespec deadline = add_ns(clock.next_wakeup(), static_cast<long>(o.deadline_fraction * T * 1e9));
      const SolveResult* res = nullptr;
      if (ticket != 0) {
        // Poll until the result is there or the deadline passes; send at once.
        timespec now{};
        for (;;) {
          res = optimizer.poll(ticket);
          clock_gettime(CLOCK_MONOTONIC, &now);
          if (res != nullptr || diff_us(now, deadline) >= 0.0) break;
          const timespec nap = add_ns(now, 20000);  // 20 us
          clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, nap.tv_sec > deadline.tv_sec ||
                                                                   (nap.tv_sec == deadline.tv_sec && nap.tv_nsec > deadline.tv_nsec)
                                                               ? &deadline
                                                               : &nap,
                          nullptr);
        }
        if (res == nullptr) {
          optimizer.abandon(ticket);
          ++st.late;
        }
      } else {
        ++st.busy;
      }
      const ControlStep& s = ctrl.finish(u_r, res);
      err.integrate(T);
      if (res != nullptr) {
        ++st.optimizer_used;
        solve.push_back(res->solve_us);
      }
      st.fallback_periods += s.fallback;
      st.clipped_periods += s.clipped;
      for (int i = 0; i < 4; ++i) cf.u[static_cast<std::size_t>(i)] = s.u(i);
      cf.flags = static_cast<std::uint8_t>((s.fallback ? io::ControlFrame::kFallback : 0) |
                                           (s.clipped ? io::ControlFrame::kClipped : 0));
      for (int i = 0; i < 24; ++i) {
        rec.x[i] = xt(i);
        rec.x_bar[i] = s.x_bar(i);
      }
      for (int i = 0; i < 10; ++i) rec.ref[i] = r.q(i);
      for (int i = 0; i < 4; ++i) {
        rec.u_bar[i] = s.u_bar(i);
        rec.u[i] = s.u(i);
      }
      rec.status = static_cast<std::int32_t>(s.status);
      rec.iterations = s.iterations;
      rec.solve_us = res != nullptr ? res->solve_us : 0.0;
      rec.fallback = s.fallback;
      rec.clipped = s.clipped;
      rec.in_tube = s.in_tube;
      for (int i = 0; i < 3; ++i) rec.d_hat[i] = s.d_hat(i);
    }
    io::encode(cf, out);
    if (!link.write_all(out.data(), out.size(), 2)) ++st.send_failures;
    if (telemetry) telemetry->push(rec);
  }
  st.skipped = clock.skipped();
  st.link = decoder.stats();
  if (telemetry) {
    st.telemetry_records = telemetry->pushed();
    st.telemetry_dropped = telemetry->dropped();
  }
  std::sort(latency.begin(), latency.end());
  if (!latency.empty()) {
    st.wake_latency_max_us = latency.back();
    st.wake_latency_p99_us = latency[std::min(latency.size() - 1, static_cast<std::size_t>(0.99 * latency.size()))];
  }
  std::sort(solve.begin(), solve.end());
  if (!solve.empty()) {
    st.solve_p50_us = solve[solve.size() / 2];
    st.solve_max_us = solve.back();
  }
  return st;
}

}  // namespace tmpc
