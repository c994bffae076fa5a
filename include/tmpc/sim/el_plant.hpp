// Euler-Lagrange plant: the nonlinear model (5.3) integrated by classical RK4 with a
// fixed sub-step (1 ms by default), the input held over each period, the
// disturbance force evaluated at each RK4 stage time.
#pragma once

#include "tmpc/sim/disturbance.hpp"
#include "tmpc/sim/plant.hpp"

namespace tmpc {

class ElPlant final : public Plant {
 public:
  ElPlant(const VehicleParams& params, DisturbanceSchedule disturbance, double substep);

  void reset(const State20& x0, double t0) override;
  void advance(const Eigen::Vector4d& u, double dt) override;
  const State20& state() const override { return x_; }
  double time() const override { return t_; }
  Eigen::Vector3d disturbance() const override { return disturbance_.force(t_); }
  std::string name() const override { return "el"; }

  const TiltrotorModel& model() const { return model_; }

 private:
  TiltrotorModel model_;
  DisturbanceSchedule disturbance_;
  double substep_;
  State20 x_ = State20::Zero();
  double t_ = 0.0;
};

}  // namespace tmpc
