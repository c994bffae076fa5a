// Euler-Lagrange plant: the nonlinear model (5.3) integrated by classical RK4 with a
// fixed sub-step (1 ms by default), the input held over each period, the
// disturbances on the load and the body taken at each sub-step's midpoint.
#pragma once

#include "tmpc/model/dynamics.hpp"
#include "tmpc/sim/disturbance.hpp"
#include "tmpc/sim/plant.hpp"

namespace tmpc {

class ElPlant final : public Plant {
 public:
  ElPlant(const VehicleParams& params, DisturbanceProfile disturbance, double substep);

  int states() const override { return kNx; }
  int inputs() const override { return kNu; }
  void reset(const Eigen::VectorXd& x0, double t0) override;
  void advance(const Eigen::VectorXd& u, double dt) override;
  const Eigen::VectorXd& state() const override { return state_; }
  double time() const override { return t_; }
  Eigen::Vector3d disturbance() const override { return disturbance_.load_force(t_); }
  std::string name() const override { return "el"; }

  const TiltrotorModel& model() const { return model_; }

 private:
  TiltrotorModel model_;
  DisturbanceProfile disturbance_;
  double substep_;
  State20 x_ = State20::Zero();
  Eigen::VectorXd state_ = Eigen::VectorXd::Zero(kNx);
  double t_ = 0.0;
};

}  // namespace tmpc
