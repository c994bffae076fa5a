// The plant process loop (see plant_loop.hpp).
#include "tmpc/sim/plant_loop.hpp"

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
  const double T = cfg.sample_time;
  const long periods = o.duration_s > 0.0 ? static_cast<long>(o.duration_s / T + 0.5) : -1;
  io::Decoder decoder(io::FrameType::Control);
  std::vector<std::uint8_t> out;
  std::uint8_t buf[1024];
  std::array<double, 10> sq{};
  TrackingError err;
  PlantLoopStats st;
  // Paced by the controller: after each state frame the plant waits for the control
  // (at most 1.5 periods of wall time), then integrates one period with it, so the
  // loop runs in real time at the controller's clock with the compute delay inside
  // the period; a silent controller leaves the last input held (as on a vehicle).
  std::uint32_t seq = 0;
  const long wait_ns = static_cast<long>(1.5 * T * 1e9);
  while (!stop.load(std::memory_order_relaxed) && (periods < 0 || st.periods < periods)) {
    io::StateFrame sf;
    sf.seq = ++seq;
    sf.time = plant->time();
    for (int i = 0; i < 20; ++i) sf.x[static_cast<std::size_t>(i)] = plant->state()(i);
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
    plant->advance(u, T);
    ++st.periods;
    const State20& x = plant->state();
    const Eigen::VectorXd& e = err.update(x, traj.at(plant->time()));  // the true tracking error
    for (int i = 0; i < 10; ++i) sq[static_cast<std::size_t>(i)] += e(i) * e(i);
    st.max_position_error = std::max(st.max_position_error, e.head<3>().cwiseAbs().maxCoeff());
    if (!x.allFinite() || st.max_position_error > 50.0) {
      st.diverged = true;
      break;
    }
  }
  for (int i = 0; i < 10; ++i) {
    st.rmse[static_cast<std::size_t>(i)] = std::sqrt(sq[static_cast<std::size_t>(i)] / std::max(1L, st.periods));
  }
  st.link = decoder.stats();
  return st;
}

}  // namespace tmpc
