// The plant's side of the link, scripted for loop tests: one prepared state frame
// per period (an empty one: nothing arrives that period), delivered once, and every
// control frame the loop writes taken and decoded; a hook sees the period count after
// each control (to switch counters on, or stop the loop).
#pragma once

#include <cstring>
#include <functional>
#include <utility>
#include <vector>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"
#include "tmpc/model/reference.hpp"

namespace tmpc::test {

class ScriptedPlant : public io::Transport {
 public:
  ScriptedPlant(std::vector<std::vector<std::uint8_t>> frames, std::function<void(int)> after_control)
      : frames_(std::move(frames)), after_control_(std::move(after_control)) {
    controls_.reserve(frames_.size() + 4096);  // the loop under test must not see this allocate
  }
  long read_some(std::uint8_t* buf, std::size_t cap) override {
    if (delivered_ || period_ >= static_cast<int>(frames_.size())) return 0;
    const std::vector<std::uint8_t>& f = frames_[static_cast<std::size_t>(period_)];
    const std::size_t n = std::min(cap, f.size());
    if (n > 0) std::memcpy(buf, f.data(), n);  // an empty frame's data() may be null
    delivered_ = true;
    return static_cast<long>(n);
  }
  bool write_all(const std::uint8_t* b, std::size_t n, int) override {
    ++period_;
    delivered_ = false;
    bool got = false;
    for (std::size_t i = 0; i < n; ++i) got = decoder_.push(b[i]) || got;
    controls_.push_back(got ? decoder_.control() : io::ControlFrame{});
    after_control_(period_);
    return true;
  }
  int controls() const { return period_; }
  /// The control frame of period k (1-based), as decoded (n = 0: none decoded).
  const io::ControlFrame& control(int k) const { return controls_[static_cast<std::size_t>(k - 1)]; }

 private:
  std::vector<std::vector<std::uint8_t>> frames_;
  std::function<void(int)> after_control_;
  io::Decoder decoder_{io::control_decoder_settings(4)};
  std::vector<io::ControlFrame> controls_;
  int period_ = 0;
  bool delivered_ = false;
};

/// The wire bytes of a state frame of the plant at reference point r, plus `offset`
/// (20 entries) on the measured state.
inline std::vector<std::uint8_t> state_bytes(std::uint32_t session, std::uint32_t seq, double t, const ReferencePoint& r,
                                             const Eigen::VectorXd& offset = Eigen::VectorXd::Zero(20)) {
  io::StateFrame s;
  s.session = session;
  s.seq = seq;
  s.time = t;
  s.n = 20;
  for (int i = 0; i < 10; ++i) {
    s.x[static_cast<std::size_t>(i)] = r.q(i) + offset(i);
    s.x[static_cast<std::size_t>(10 + i)] = r.qd(i) + offset(10 + i);
  }
  std::vector<std::uint8_t> bytes;
  io::encode(s, bytes);
  return bytes;
}

}  // namespace tmpc::test

#include <memory>

#include "tmpc/sim/el_plant.hpp"

namespace tmpc::test {

/// A closed loop on the loop's own schedule: a plant (started where the test wants
/// it), each period's state frame its state (passed through `edit`, which may offset
/// or drop it), each control frame advancing it one period with the inputs it carries.
class SimulatedPlantLink : public io::Transport {
 public:
  using Edit = std::function<std::vector<std::uint8_t>(int period, const io::StateFrame& f)>;
  SimulatedPlantLink(std::unique_ptr<Plant> plant, double sample_time, Edit edit)
      : plant_(std::move(plant)), T_(sample_time), edit_(std::move(edit)),
        decoder_(io::control_decoder_settings(plant_->inputs())), u_(Eigen::VectorXd::Zero(plant_->inputs())) {}
  /// The tiltrotor's Euler-Lagrange plant started on the reference at t = 0.
  SimulatedPlantLink(const Config& cfg, ReferenceGenerator& traj, Edit edit)
      : SimulatedPlantLink(std::make_unique<ElPlant>(cfg.vehicle, DisturbanceProfile{}, cfg.simulation.substep),
                           cfg.sample_time, std::move(edit)) {
    const ReferencePoint r0 = traj.at(0.0);
    Eigen::VectorXd x0(20);
    x0 << r0.q, r0.qd;
    plant_->reset(x0, 0.0);
  }
  long read_some(std::uint8_t* buf, std::size_t cap) override {
    if (delivered_) return 0;
    delivered_ = true;
    io::StateFrame f;
    f.session = 0x5151;
    f.seq = static_cast<std::uint32_t>(period_ + 1);
    f.time = plant_->time();
    f.n = static_cast<std::uint8_t>(plant_->states());
    for (int i = 0; i < plant_->states(); ++i) f.x[static_cast<std::size_t>(i)] = plant_->state()(i);
    std::vector<std::uint8_t> bytes;
    if (edit_) {
      bytes = edit_(period_, f);
    } else {
      io::encode(f, bytes);
    }
    const std::size_t n = std::min(cap, bytes.size());
    std::memcpy(buf, bytes.data(), n);
    return static_cast<long>(n);
  }
  bool write_all(const std::uint8_t* b, std::size_t n, int) override {
    for (std::size_t i = 0; i < n; ++i) {
      if (decoder_.push(b[i])) {
        for (int k = 0; k < plant_->inputs(); ++k) u_(k) = decoder_.control().u[static_cast<std::size_t>(k)];
      }
    }
    if (act_) {
      u_act_ = u_;
      act_(period_, u_act_);  // a fault between the link and the actuators
      plant_->advance(u_act_, T_);
    } else {
      plant_->advance(u_, T_);
    }
    ++period_;
    delivered_ = false;
    return true;
  }
  const Plant& plant() const { return *plant_; }
  int periods() const { return period_; }
  /// The inputs the plant applies, edited from those received (an actuator fault).
  void set_actuator_edit(std::function<void(int period, Eigen::VectorXd& u)> act) { act_ = std::move(act); }

 private:
  std::unique_ptr<Plant> plant_;
  double T_;
  Edit edit_;
  io::Decoder decoder_;
  Eigen::VectorXd u_, u_act_;
  std::function<void(int, Eigen::VectorXd&)> act_;
  int period_ = 0;
  bool delivered_ = false;
};

/// The wire bytes of `f` with `offset` added to its measured state.
inline std::vector<std::uint8_t> offset_bytes(io::StateFrame f, const Eigen::VectorXd& offset) {
  for (int i = 0; i < 20; ++i) f.x[static_cast<std::size_t>(i)] += offset(i);
  std::vector<std::uint8_t> bytes;
  io::encode(f, bytes);
  return bytes;
}

}  // namespace tmpc::test
