// The on-board loop (see controller_loop.hpp).
#include "tmpc/runtime/controller_loop.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "tmpc/runtime/controller_solver.hpp"
#include "tmpc/runtime/percentiles.hpp"
#include "tmpc/runtime/reference_source.hpp"
#include "tmpc/runtime/state_gate.hpp"
#include "tmpc/runtime/telemetry.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/runtime/tube_controller.hpp"
#include "tmpc/runtime/yaw_governor.hpp"

namespace tmpc {

ControllerLoopStats run_controller_loop(const ControllerArtifact& a, io::Transport& link,
                                        const ControllerLoopOptions& o, const std::atomic<bool>& stop,
                                        const ControllerLoopSeams& seams) {
  // Everything that allocates happens here, before the loop; everything comes from the
  // artifact's records (no YAML).
  if (!o.trajectory) throw std::invalid_argument("controller loop: no trajectory to fly");
  if (!(o.time_scale >= 1.0 && o.time_scale <= 1000.0)) {
    throw std::invalid_argument("controller loop: time_scale must be in [1, 1000], got " + std::to_string(o.time_scale));
  }
  const double T = a.sample_time;
  const double T_wall = T * o.time_scale;  // the period on the wall clock
  const int p = a.measured, m = a.m;
  SolverOptions so;
  so.eps_abs = so.eps_rel = a.solver.admm_epsilon;
  so.eta = a.solver.admm_eta;
  // A solve never outlives its period's deadline: past it the answer is useless, and
  // still running it would make the next period busy (the fallback twice).
  so.time_budget_us = o.deadline_fraction * T_wall * 1e6;
  const TubeControllerOptions law = flight_law_options(a, o.tube_law, o.estimator);
  TubeController ctrl(a, nullptr, law);
  std::unique_ptr<AsyncOptimizer> own_optimizer;
  Optimizer* optimizer = seams.optimizer;
  if (optimizer == nullptr) {
    own_optimizer = std::make_unique<AsyncOptimizer>(
        make_controller_solver(o.solver, a, so, o.explicit_law, law.offset_free), ctrl.parameters());
    optimizer = own_optimizer.get();
  }
  // Yaw into the force: the reference's yaw turned by the governor, which keeps its
  // offset across restarts (the vehicle stays where it turned). Its rate is checked
  // against the trajectory for an hour when the loop runs without an end.
  std::unique_ptr<YawGovernor> governor;
  std::shared_ptr<const Trajectory> flown = o.trajectory;
  if (o.yaw_into_force) {
    governor = std::make_unique<YawGovernor>(
        yaw_governor_settings(a, *o.trajectory, o.duration_s > 0.0 ? o.duration_s : 3600.0));
    flown = std::make_shared<GovernedTrajectory>(o.trajectory, governor.get());
  }
  std::unique_ptr<ReferenceSource> reference = make_reference_source(a, flown);
  // The measured states, their kinds and the gates.
  const std::vector<StateKind> kinds = a.measured_kinds();
  const int yaw_row = static_cast<int>(std::find(kinds.begin(), kinds.end(), StateKind::Yaw) - kinds.begin());
  const Eigen::VectorXd half = a.N_x.head(p).cwiseInverse();
  StateGate gate(a.A.topLeftCorner(p, p), a.B.topRows(p), a.N_x.head(p), a.N_u, kinds,
                 state_gate_settings(a.link, kinds, half, T));
  io::Decoder decoder(state_decoder_settings(a.link, kinds));
  const int watchdog = o.silent_periods > 0 ? o.silent_periods : a.link.watchdog_periods;
  TrackingError err(kinds, a.integrated);
  if (o.reference_join) err.set_join(reference_join_settings(a));  // planned again at every restart (err.reset())
  if (a.envelope.any_yaw()) err.set_yaw_frame(a.envelope.yaw);
  std::unique_ptr<TelemetryWriter> telemetry;
  if (!o.telemetry_csv.empty()) {
    telemetry = std::make_unique<TelemetryWriter>(
        o.telemetry_csv, TelemetryLayout{a.state_names, a.input_names, p, std::min(3, static_cast<int>(a.D.cols())),
                                        o.solver_note.empty() ? "" : "solver " + o.solver + ": " + o.solver_note});
  }
  std::vector<std::uint8_t> out;
  out.reserve(256);
  std::uint8_t buf[1024];
  const long max_periods = o.duration_s > 0.0 ? static_cast<long>(o.duration_s / T + 0.5) : -1;
  std::vector<double> latency, solve;
  latency.reserve(max_periods > 0 ? static_cast<std::size_t>(max_periods) : 1u << 20);
  solve.reserve(latency.capacity());
  Eigen::VectorXd e_meas = Eigen::VectorXd::Zero(p), u_tilde = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(p), x_cand = x, x_r_last = x, x_r_cand = x;
  Eigen::VectorXd u_r = Eigen::VectorXd::Zero(m), u_r_cand = u_r;
  ControllerLoopStats st;
  st.watchdog_periods = watchdog;
  st.session = o.session != 0 ? o.session : io::draw_session_id();
  st.observer = law.offset_free ? law.observer : "none";
  st.realtime = apply_realtime(o.realtime);
  std::unique_ptr<PeriodicClock> own_clock;
  LoopClock* clock = seams.clock;
  if (clock == nullptr) {
    own_clock = std::make_unique<PeriodicClock>(T_wall);
    clock = own_clock.get();
  }
  io::StateFrame last{}, cand{};
  bool have_state = false;
  long silent = 0;
  std::uint32_t seq = 0;
  TelemetryRecord rec;
  Eigen::VectorXd u_safe = reference->hover_input(), u_r_sent = u_safe;
  bool controlled_last = false;   // the previous period sent the law's input for a fresh state
  double last_state_time = -1.0;  // plant time of the state that input was computed from
  if (o.ready != nullptr) o.ready->store(true);
  while (!stop.load(std::memory_order_relaxed) && (max_periods < 0 || st.periods + clock->skipped() < max_periods)) {
    const double lat = clock->wait();
    latency.push_back(lat);  // within the reserved capacity
    st.late_wakes += lat > 0.5 * T_wall * 1e6;
    if (clock->last_period_us() > 0.0) {
      st.period_jitter_max_us = std::max(st.period_jitter_max_us, std::abs(clock->last_period_us() - T_wall * 1e6));
    }
    // The newest frame the decoder accepts this period; a new session or a re-anchored
    // sequence starts a new track in the gate.
    bool got = false, new_track = false;
    for (;;) {
      const long n = link.read_some(buf, sizeof(buf));
      if (n <= 0) break;
      for (long i = 0; i < n; ++i) {
        if (decoder.push(buf[i])) {
          cand = decoder.state();
          got = true;
          new_track = new_track || decoder.new_session() || decoder.resynced();
        }
      }
    }
    bool fresh = false, restart = false;
    if (got) {
      if (new_track) gate.reset();
      for (int i = 0; i < p; ++i) x_cand(i) = cand.x[static_cast<std::size_t>(i)];
      // No trim at that time: the frame cannot be judged, it is treated as missing.
      if (reference->at(cand.time, x_r_cand, u_r_cand)) {
        err.measured(x_cand, x_r_cand, e_meas);
        const StateGate::Verdict v = gate.check(cand.time, cand.seq, e_meas, u_tilde);
        if (StateGate::accepted(v)) {
          fresh = true;
          restart = v != StateGate::Verdict::Accepted;  // a new track: the law starts from it
          last = cand;
          x = x_cand;
          x_r_last = x_r_cand;
          u_r = u_r_cand;
          st.peer_session = decoder.session();
        }
      }
    }
    silent = fresh ? 0 : silent + 1;
    have_state = have_state || fresh;
    ++st.periods;
    io::ControlFrame cf;
    cf.session = st.session;
    cf.seq = ++seq;
    cf.n = static_cast<std::uint8_t>(m);
    rec = TelemetryRecord{};
    rec.period = static_cast<std::uint64_t>(st.periods);
    rec.t = clock->elapsed_s();
    rec.wake_latency_us = lat;
    rec.period_us = clock->last_period_us();
    if (!have_state || silent > watchdog) {
      // Safe command: the last feedforward with zero servo torques (hover before any
      // state); a linear model's: zero.
      for (int i = 0; i < m; ++i) cf.u[static_cast<std::size_t>(i)] = a.model == ModelKind::Tiltrotor && i >= 2 ? 0.0 : u_safe(i);
      cf.flags = io::ControlFrame::kSafe;
      ++st.safe_periods;
      rec.safe_command = 1;
      controlled_last = false;
      u_r_sent = u_safe;
    } else {
      ++st.states;
      u_safe = u_r;
      if (restart) {
        err.reset();
        ctrl.reset(err.update(x, x_r_last));
        controlled_last = false;
        ++st.restarts;
        rec.restart = 1;
      }
      const Eigen::VectorXd& xt = err.update(x, x_r_last);
      // The observer uses a residual only across one period of the law's own input,
      // and only when the plant moved by one period since that state (a stall of either
      // side makes the residual span several periods under inputs it did not see).
      const bool one_period = std::abs(last.time - last_state_time - T) < 0.5 * T;
      const std::uint64_t ticket = optimizer->start(ctrl.prepare(xt, fresh && controlled_last && one_period));
      controlled_last = fresh;
      last_state_time = last.time;
      const std::int64_t deadline =
          clock->next_wakeup_ns() + static_cast<std::int64_t>(o.deadline_fraction * T_wall * 1e9);
      const SolveResult* res = nullptr;
      if (ticket != 0) {
        // Poll until the result is there or the deadline passes; send at once.
        for (;;) {
          res = optimizer->poll(ticket);
          const std::int64_t now = clock->now_ns();
          if (res != nullptr || now >= deadline) break;
          clock->sleep_until_ns(std::min(now + 20000, deadline));  // 20 us naps
        }
        if (res == nullptr) {
          optimizer->abandon(ticket);
          ++st.late;
        }
      } else {
        ++st.busy;
      }
      const ControlStep& s = ctrl.finish(u_r, res);
      err.integrate(T);
      if (governor && fresh && s.d_hat.size() >= 2) {
        governor->update(s.d_hat.head<2>(), x_r_last(yaw_row) - a.envelope.yaw, o.trajectory->at(last.time).psi, T);
      }
      if (res != nullptr) {
        ++st.optimizer_used;
        solve.push_back(res->solve_us);
      }
      st.fallback_periods += s.fallback;
      st.reverted_periods += s.reverted;
      st.clipped_periods += s.clipped;
      st.softened_periods += s.softened;
      rec.softened = s.softened;
      rec.slack_max = s.slack_max;
      rec.filtered = s.filtered;
      rec.noise_level = s.noise_level;
      rec.gated = static_cast<std::uint8_t>(s.gated_rows);
      rec.step = static_cast<std::uint8_t>(step_code(s));
      for (int i = 0; i < m; ++i) cf.u[static_cast<std::size_t>(i)] = s.u(i);
      cf.flags = static_cast<std::uint8_t>((s.fallback ? io::ControlFrame::kFallback : 0) |
                                           (s.clipped ? io::ControlFrame::kClipped : 0));
      u_r_sent = u_r;
      for (int i = 0; i < a.n; ++i) {
        rec.x[i] = xt(i);
        rec.x_bar[i] = s.x_bar(i);
      }
      for (int i = 0; i < p; ++i) rec.ref[i] = x_r_last(i);
      for (int i = 0; i < m; ++i) {
        rec.u_bar[i] = s.u_bar(i);
        rec.u[i] = s.u(i);
      }
      rec.status = static_cast<std::int32_t>(s.status);
      rec.iterations = s.iterations;
      rec.solve_us = res != nullptr ? res->solve_us : 0.0;
      rec.fallback = s.fallback;
      rec.clipped = s.clipped;
      rec.in_tube = s.in_tube;
      for (Eigen::Index i = 0; i < std::min<Eigen::Index>(3, s.d_hat.size()); ++i) rec.d_hat[i] = s.d_hat(i);
    }
    // The input the plant holds until the next frame, in error coordinates (the gate's
    // prediction of the next state).
    for (int i = 0; i < m; ++i) u_tilde(i) = cf.u[static_cast<std::size_t>(i)] - u_r_sent(i);
    io::encode(cf, out);
    if (!link.write_all(out.data(), out.size(), 2)) ++st.send_failures;
    const io::LinkCounts counts = decoder.counts().plus(gate.counts());
    for (std::size_t i = 0; i < io::kRejectReasons; ++i) rec.link_rejects[i] = static_cast<std::int32_t>(counts.rejected[i]);
    rec.peer_session = st.peer_session;
    if (telemetry) telemetry->push(rec);
  }
  st.skipped = clock->skipped();
  // Accepted: what passed both the decoder and the gate.
  st.link = decoder.counts().plus(gate.counts());
  st.link.accepted = gate.counts().accepted;
  if (telemetry) {
    st.telemetry_records = telemetry->pushed();
    st.telemetry_dropped = telemetry->dropped();
  }
  st.wake_latency_p99_us = percentile(latency, 0.99);
  st.wake_latency_max_us = latency.empty() ? 0.0 : latency.back();
  st.solve_p50_us = percentile(solve, 0.5);
  st.solve_max_us = solve.empty() ? 0.0 : solve.back();
  return st;
}

}  // namespace tmpc
