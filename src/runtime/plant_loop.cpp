// The plant process loop (see plant_loop.hpp).
#include "tmpc/runtime/plant_loop.hpp"

#include <cmath>
#include <vector>

#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/runtime/realtime.hpp"
#include "tmpc/runtime/tracking_error.hpp"
#include "tmpc/sim/plant.hpp"

namespace tmpc {

PlantLoopStats run_plant_loop(const Config& cfg, io::Transport& link, const PlantLoopOptions& o,
                              const std::atomic<bool>& stop) {
  const TiltrotorModel model(cfg.vehicle);
  const HelixTrajectory traj(cfg.reference, model);
  auto plant = make_plant(o.plant, cfg, o.disturbance, o.run);
  const ReferencePoint r0 = traj.at(0.0);
  State20 x0;
  x0 << r0.q, r0.qd;  // start on the reference (E8)
  plant->reset(x0, 0.0);
  Eigen::Vector4d u = feedforward(model, r0);
  // The plant's safe command: hover thrust, servo torques off.
  const Eigen::Vector4d u_safe(traj.equilibrium().u(0), traj.equilibrium().u(1), 0.0, 0.0);
  const double T = cfg.sample_time;
  const double hold_s = o.hold_s >= 0.0 ? o.hold_s : cfg.link.plant_hold_s;
  const long periods = o.duration_s > 0.0 ? static_cast<long>(o.duration_s / T + 0.5) : -1;
  io::DecoderSettings ds = io::control_decoder_settings(4);
  ds.sequence_window = static_cast<std::uint32_t>(cfg.link.sequence_window);
  ds.resync_frames = cfg.link.resync_frames;
  ds.session_confirm = cfg.link.session_confirm;
  io::Decoder decoder(ds);
  std::vector<std::uint8_t> out;
  std::uint8_t buf[1024];
  std::array<double, 10> sq{};
  TrackingError err;
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
  const long wait_ns = static_cast<long>(1.5 * T * 1e9);
  while (!stop.load(std::memory_order_relaxed) && (periods < 0 || st.periods < periods)) {
    io::StateFrame sf;
    sf.session = st.session;
    sf.seq = ++seq;
    sf.time = plant->time();
    sf.n = kNx;
    for (int i = 0; i < kNx; ++i) sf.x[static_cast<std::size_t>(i)] = plant->state()(i);
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
          for (int k = 0; k < 4; ++k) u(k) = c.u[static_cast<std::size_t>(k)];
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
    if (silent_s > hold_s + 1e-9) {
      if (!lost) {
        ++st.link_losses;
        if (st.first_link_loss_s < 0.0) st.first_link_loss_s = plant->time();
      }
      lost = true;
      ++st.safe_command_periods;
      plant->advance(u_safe, T);
      for (int k = 0; k < 4; ++k) st.last_input[static_cast<std::size_t>(k)] = u_safe(k);
    } else {
      lost = false;
      st.held_periods += !got;
      plant->advance(u, T);
      for (int k = 0; k < 4; ++k) st.last_input[static_cast<std::size_t>(k)] = u(k);
    }
    ++st.periods;
    const State20& x = plant->state();
    const Eigen::VectorXd& e = err.update(x, traj.at(plant->time()));  // the true tracking error
    for (int i = 0; i < 10; ++i) sq[static_cast<std::size_t>(i)] += e(i) * e(i);
    st.max_position_error = std::max(st.max_position_error, e.head<3>().cwiseAbs().maxCoeff());
    position_error.push_back(e.head<3>().cwiseAbs().maxCoeff());
    if (!x.allFinite() || st.max_position_error > 50.0) {
      st.diverged = true;
      break;
    }
  }
  for (int i = 0; i < 10; ++i) {
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
