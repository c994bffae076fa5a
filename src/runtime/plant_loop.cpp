// The plant process loop (see plant_loop.hpp).
#include "tmpc/runtime/plant_loop.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "tmpc/runtime/realtime.hpp"
#include "tmpc/runtime/reference_source.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/sim/noise.hpp"
#include "tmpc/sim/plant_model.hpp"

namespace tmpc {

PlantSetup PlantSetup::from_config(const Config& cfg) {
  PlantSetup s;
  s.model = PlantModel::from_config(cfg);
  s.attitude = cfg.attitude;
  s.sample_time = cfg.sample_time;
  s.link = cfg.link;
  s.inputs = cfg.inputs();
  if (cfg.model == ModelKind::Tiltrotor && cfg.envelope.any_yaw()) s.yaw_frame = cfg.envelope.yaw;
  return s;
}

PlantSetup PlantSetup::from_artifact(const ControllerArtifact& a) {
  PlantSetup s;
  s.model.kind = a.model;
  s.model.vehicle = a.vehicle;
  s.model.A = a.linear_A;
  s.model.B = a.linear_B;
  s.model.D = a.linear_D;
  s.model.substep = a.substep;
  s.model.kinds = a.measured_kinds();
  s.attitude = a.attitude;
  s.sample_time = a.sample_time;
  s.link = a.link;
  s.inputs = a.m;
  if (a.model == ModelKind::Tiltrotor && a.envelope.any_yaw()) s.yaw_frame = a.envelope.yaw;
  return s;
}

PlantLoopStats run_plant_loop(const PlantSetup& setup, const Scenario& sc, io::Transport& link,
                              const PlantLoopOptions& o, const std::atomic<bool>& stop) {
  const PlantModel& pm = setup.model;
  const int p = static_cast<int>(pm.kinds.size()), m = setup.inputs;
  std::unique_ptr<ReferenceSource> reference =
      make_reference_source(pm.kind, pm.vehicle, setup.attitude, m, sc.trajectory);
  Eigen::VectorXd x_r = Eigen::VectorXd::Zero(p), u_r = Eigen::VectorXd::Zero(m);
  reference->at(0.0, x_r, u_r);
  auto plant = make_scenario_plant(pm, sc, x_r, o.run, o.seed, o.plant);
  Eigen::VectorXd u = u_r;  // the feedforward until the first control
  // The plant's safe command: hover thrust, servo torques off (a linear plant: zero).
  Eigen::VectorXd u_safe = reference->hover_input();
  if (pm.kind == ModelKind::Tiltrotor) u_safe.tail(2).setZero();
  const double T = setup.sample_time;
  const double hold_s = o.hold_s >= 0.0 ? o.hold_s : setup.link.plant_hold_s;
  const double duration = o.duration_s >= 0.0 ? o.duration_s : sc.duration;
  const long periods = duration > 0.0 ? static_cast<long>(duration / T + 0.5) : -1;
  io::DecoderSettings ds = io::control_decoder_settings(static_cast<std::size_t>(m));
  ds.sequence_window = static_cast<std::uint32_t>(setup.link.sequence_window);
  ds.resync_frames = setup.link.resync_frames;
  ds.session_confirm = setup.link.session_confirm;
  io::Decoder decoder(ds);
  SensorNoise noise(sc.noise, pm.kinds);
  std::vector<std::uint8_t> out;
  std::uint8_t buf[1024];
  std::vector<double> sq(static_cast<std::size_t>(p), 0.0);
  TrackingError err(pm.kinds, {});
  if (setup.yaw_frame) err.set_yaw_frame(*setup.yaw_frame);
  Eigen::VectorXd measured = Eigen::VectorXd::Zero(p), e = measured;
  PlantLoopStats st;
  st.session = o.session != 0 ? o.session : io::draw_session_id();
  // Paced by the controller: after each state frame the plant waits for the control
  // (at most 1.5 periods of wall time), then integrates one period with it, so the
  // loop runs in real time at the controller's clock with the compute delay inside
  // the period.
  std::uint32_t seq = 0;
  double silent_s = 0.0;
  bool lost = false;
  long run = 0;  // consecutive periods without a control
  std::vector<double> position_error;  // per period, for the final second
  if (periods > 0) position_error.reserve(static_cast<std::size_t>(periods));
  if (!(o.time_scale >= 1.0 && o.time_scale <= 1000.0)) {
    throw std::invalid_argument("plant loop: time_scale must be in [1, 1000], got " + std::to_string(o.time_scale));
  }
  const long wait_ns = static_cast<long>(1.5 * T * o.time_scale * 1e9);
  while (!stop.load(std::memory_order_relaxed) && (periods < 0 || st.periods < periods)) {
    io::StateFrame sf;
    sf.session = st.session;
    sf.seq = ++seq;
    sf.time = plant->time();
    sf.n = static_cast<std::uint8_t>(p);
    measured = plant->state();
    noise.apply(measured);
    for (int i = 0; i < p; ++i) sf.x[static_cast<std::size_t>(i)] = measured(i);
    io::encode(sf, out);
    link.write_all(out.data(), out.size(), 2);
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    const timespec give_up = add_ns(now, wait_ns);
    bool got = false;
    while (!got && !stop.load(std::memory_order_relaxed)) {
      const long n = link.read_some(buf, sizeof(buf));
      for (long i = 0; i < n; ++i) {
        if (decoder.push(buf[i])) {
          got = true;
          const io::ControlFrame& c = decoder.control();
          for (int k = 0; k < m; ++k) u(k) = c.u[static_cast<std::size_t>(k)];
          st.safe_frames += (c.flags & io::ControlFrame::kSafe) != 0;
          st.fallback_frames += (c.flags & io::ControlFrame::kFallback) != 0;
          st.controller_sessions += decoder.new_session();
          st.peer_session = c.session;
        }
      }
      if (got || n < 0) break;
      clock_gettime(CLOCK_MONOTONIC, &now);
      if (diff_us(now, give_up) >= 0.0) break;
      const timespec nap = add_ns(now, 50000);  // 50 us
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &nap, nullptr);
    }
    st.controls += got;
    st.periods_without_control += !got;
    if (got && decoder.new_session()) st.silent_periods_last_session = 0;
    st.silent_periods_last_session += !got && st.controls > 0;
    run = got ? 0 : run + (st.controls > 0);
    st.longest_silence_periods = std::max(st.longest_silence_periods, run);
    silent_s = got ? 0.0 : silent_s + T;
    const bool safe = silent_s > hold_s + 1e-9;
    if (safe) {
      if (!lost) {
        ++st.link_losses;
        if (st.first_link_loss_s < 0.0) st.first_link_loss_s = plant->time();
      }
      ++st.safe_command_periods;
    } else {
      st.held_periods += !got;
    }
    lost = safe;
    const Eigen::VectorXd& applied = safe ? u_safe : u;
    plant->advance(applied, T);
    st.last_input.assign(applied.data(), applied.data() + applied.size());
    ++st.periods;
    // The true tracking error (no noise).
    if (!reference->at(plant->time(), x_r, u_r)) {
      st.diverged = true;
      break;
    }
    err.measured(plant->state(), x_r, e);
    for (int i = 0; i < p; ++i) sq[static_cast<std::size_t>(i)] += e(i) * e(i);
    double pos = 0.0;
    for (int i = 0; i < p; ++i) {
      if (pm.kinds[static_cast<std::size_t>(i)] == StateKind::Position) pos = std::max(pos, std::abs(e(i)));
    }
    st.max_position_error = std::max(st.max_position_error, pos);
    position_error.push_back(pos);
    if (!plant->state().allFinite() || st.max_position_error > 50.0) {
      st.diverged = true;
      break;
    }
  }
  st.rmse.resize(static_cast<std::size_t>(p));
  for (int i = 0; i < p; ++i) {
    st.rmse[static_cast<std::size_t>(i)] = std::sqrt(sq[static_cast<std::size_t>(i)] / std::max(1L, st.periods));
  }
  const std::size_t final = std::min(position_error.size(), static_cast<std::size_t>(std::lround(1.0 / T)));
  for (std::size_t k = position_error.size() - final; k < position_error.size(); ++k) {
    st.max_position_error_final_s = std::max(st.max_position_error_final_s, position_error[k]);
  }
  st.link = decoder.counts();
  return st;
}

}  // namespace tmpc
