// The tube control law, thesis (5.9), in normalized coordinates:
//   u = u_r + N_u^-1 (u_bar(0) + K (x_tilde_n - x_bar_n))
// with the nominal state propagated by the nominal model (Mayne's tube MPC):
//   x_bar+ = A x_bar + B u_bar(0)
// (optionally re-initialised to the measured error when that lies in X_bar), the
// applied input clipped to the actuator limits (counted), and the LQR fallback
// u = u_r + N_u^-1 K_lqr x_tilde_n used when the optimizer fails or is late.
// No allocation in step(); it never throws.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "tmpc/solvers/solver.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct TubeControllerOptions {
  bool reinitialize_nominal = false;  ///< x_bar := x_tilde when x_tilde is in X_bar
};

/// What one period decided.
struct ControlStep {
  Eigen::Vector4d u = Eigen::Vector4d::Zero();      ///< applied input (physical, clipped)
  Eigen::Vector4d u_bar = Eigen::Vector4d::Zero();  ///< nominal input u_bar(0), physical error units
  Eigen::VectorXd x_bar;                            ///< nominal state used (normalized)
  SolveStatus status = SolveStatus::Converged;
  int iterations = 0;
  double solve_us = 0.0;
  bool fallback = false;  ///< the LQR law was applied
  bool clipped = false;   ///< an input hit an actuator limit
  bool in_tube = true;    ///< x_tilde - x_bar inside the interval hull of Z
  double tube_ratio = 0.0;  ///< max_i |x_tilde - x_bar - c_Z|_i / radius_i (<= 1: inside)
  int tube_worst = 0;       ///< the state i of that maximum
  bool in_state_box = true;  ///< x_tilde inside X
};

class TubeController {
 public:
  /// `solver` may be null when the optimizer runs elsewhere (AsyncOptimizer): then use
  /// prepare() and finish() instead of step().
  TubeController(const ControllerArtifact& a, std::unique_ptr<QpSolver> solver, TubeControllerOptions opt = {});

  /// One period: x_tilde (physical, 24 error states), u_r the feedforward, and whether
  /// the optimizer's answer arrived in time (false: the fallback is applied).
  /// Equals prepare(), a solve from the returned nominal state, finish().
  const ControlStep& step(const Eigen::VectorXd& x_tilde, const Eigen::Vector4d& u_r, bool optimizer_in_time = true);
  /// First half of a period: the nominal state (normalized) the optimizer solves from.
  const Eigen::VectorXd& prepare(const Eigen::VectorXd& x_tilde);
  /// Second half: the law (5.9) with the optimizer's result, or the LQR fallback when
  /// `r` is null (late, busy), not converged, or not `in_time` (its status is still
  /// recorded). Call prepare() first in the same period.
  const ControlStep& finish(const Eigen::Vector4d& u_r, const SolveResult* r, bool in_time = true);
  /// Start the nominal state at a (physical) error state, e.g. at mission start.
  void reset(const Eigen::VectorXd& x_tilde);

  const ControllerArtifact& artifact() const { return a_; }
  long clipped_count() const { return clipped_; }
  long fallback_count() const { return fallbacks_; }

 private:
  const ControllerArtifact& a_;
  std::unique_ptr<QpSolver> solver_;
  TubeControllerOptions opt_;
  Eigen::VectorXd x_bar_, x_n_, e_, dev_, z_half_, next_;
  Eigen::Vector4d u_min_, u_max_;
  ControlStep out_;
  long clipped_ = 0, fallbacks_ = 0;
};

}  // namespace tmpc
