// Offset-free tube MPC: the steady state a constant disturbance d implies,
//   x_s = A x_s + B u_s + D d,   x_s(i) = 0 for the listed states,
// (the tracked errors and the integral states), a linear map d -> (x_s, u_s) computed
// offline. Online the nominal QP regulates x_bar - x_s with its sets shifted by
// (x_s, u_s) (MpcQpData::Tx, Tu), the nominal model predicts with the estimate d_hat,
// and the tube law adds u_s: the constant part of a disturbance leaves the tube's
// error dynamics, which (3.36) cannot bound (DESIGN.md section 4).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace tmpc {

struct DisturbanceTarget {
  Eigen::MatrixXd Tx;  ///< n x nd: x_s = Tx d
  Eigen::MatrixXd Tu;  ///< m x nd: u_s = Tu d
};

/// Solves [I - A, -B; S, 0] [x_s; u_s] = [D d; 0] column by column (S selects
/// `zero_states`), the minimum-norm solution where it is not unique. Throws
/// std::invalid_argument naming the disturbance channel when no steady state exists
/// (relative residual above 1e-8), or on inconsistent sizes.
DisturbanceTarget steady_state_target(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                                      const std::vector<int>& zero_states);

/// Least-squares disturbance from a one-step prediction residual r = x_next - A x - B u
/// on the listed rows only: d = argmin sum_{i in rows} (r - D d)_i^2, returned as the
/// nd x n map r -> d (zero columns elsewhere). Throws when D on those rows has not
/// full column rank, or a row is out of range.
Eigen::MatrixXd disturbance_pseudo_inverse(const Eigen::MatrixXd& D, const std::vector<int>& rows);

}  // namespace tmpc
