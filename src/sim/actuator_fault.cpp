// Actuator faults (see actuator_fault.hpp).
#include "tmpc/sim/actuator_fault.hpp"

#include <cmath>
#include <stdexcept>

namespace tmpc {

ActuatorFaults::ActuatorFaults(std::vector<ActuatorFault> faults, int inputs)
    : faults_(std::move(faults)), held_(faults_.size(), 0.0), has_held_(faults_.size(), 0) {
  for (std::size_t k = 0; k < faults_.size(); ++k) {
    const ActuatorFault& f = faults_[k];
    const std::string where = "actuator faults[" + std::to_string(k) + "]: ";
    if (f.input < 0 || f.input >= inputs) {
      throw std::invalid_argument(where + "input " + std::to_string(f.input) + " outside [0, " +
                                  std::to_string(inputs) + "): the plant has " + std::to_string(inputs) + " inputs");
    }
    if (!(f.factor >= 0.0) || !std::isfinite(f.factor)) throw std::invalid_argument(where + "factor must be finite and >= 0");
    if (!std::isfinite(f.value)) throw std::invalid_argument(where + "value must be finite");
    if (!(f.start >= 0.0) || !(f.end > f.start)) throw std::invalid_argument(where + "end must come after start >= 0");
  }
}

void ActuatorFaults::apply(double t, const Eigen::VectorXd& u, Eigen::VectorXd& applied) {
  applied = u;
  for (std::size_t k = 0; k < faults_.size(); ++k) {
    const ActuatorFault& f = faults_[k];
    if (t < f.start - 1e-9 || t >= f.end - 1e-9) continue;  // the period's start, to rounding of the clock
    double& v = applied(f.input);
    switch (f.kind) {
      case ActuatorFault::Kind::Efficiency:
        v *= f.factor;
        break;
      case ActuatorFault::Kind::Bias:
        v += f.value;
        break;
      case ActuatorFault::Kind::Stuck:
        if (!has_held_[k]) {
          held_[k] = v;
          has_held_[k] = 1;
        }
        v = held_[k];
        break;
    }
  }
}

namespace {

class FaultyPlant final : public Plant {
 public:
  FaultyPlant(std::unique_ptr<Plant> inner, std::vector<ActuatorFault> faults)
      : inner_(std::move(inner)), faults_(std::move(faults), inner_->inputs()), applied_(inner_->inputs()) {}
  int states() const override { return inner_->states(); }
  int inputs() const override { return inner_->inputs(); }
  void reset(const Eigen::VectorXd& x0, double t0) override { inner_->reset(x0, t0); }
  void advance(const Eigen::VectorXd& u, double dt) override {
    faults_.apply(inner_->time(), u, applied_);
    inner_->advance(applied_, dt);
  }
  const Eigen::VectorXd& state() const override { return inner_->state(); }
  double time() const override { return inner_->time(); }
  Eigen::Vector3d disturbance() const override { return inner_->disturbance(); }
  std::string name() const override { return inner_->name(); }

 private:
  std::unique_ptr<Plant> inner_;
  ActuatorFaults faults_;
  Eigen::VectorXd applied_;
};

}  // namespace

std::unique_ptr<Plant> with_actuator_faults(std::unique_ptr<Plant> plant, std::vector<ActuatorFault> faults) {
  if (faults.empty()) return plant;
  return std::make_unique<FaultyPlant>(std::move(plant), std::move(faults));
}

}  // namespace tmpc
