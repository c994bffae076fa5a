// Which disturbance a step hit, from the filter's innovations (tube_controller.hpp, step
// detection; README "Re-opening the lift at a step"): a generalized likelihood ratio
// over the step's innovation signature (Willsky and Jones, IEEE TAC 21, 1976).
//
// A steady Kalman filter (estimator.hpp: predict xi^- = A_a xi + B_a u, update
// xi = xi^- + L nu, nu = y - C xi^-) whose augmented state jumps by E mu at period t0
// (E: unit columns of the states a step may hit, the forces and residuals) sees, on
// top of its white innovations, the deterministic signature
//   nu(t0 + k) = C (A_a (I - L C))^k E mu = G(k) mu,   k = 0, 1, ...
// (G(0) = C E = 0 for unmeasured disturbance states; E unit columns, or any directions
// in them such as an actuator's: an input step B_j mu is the disturbance step v_j mu
// whose effect [D E_c] v_j matches B_j, Pannocchia and Rawlings 2003's input-disturbance
// model). With the innovations whitened
// by their steady deviations (z = nu / sd, rows taken as independent: an approximation),
// the log-likelihood ratio of "a step of columns E, m periods ago" against "no step",
// maximized over mu, is
//   l(m) = b(m)' M(m)^-1 b(m),  b(m) = sum_{k=1..m} G(k)' z(t - m + k),
//   M(m) = sum_{k=1..m} G(k)' G(k),  mu_hat(m) = M(m)^-1 b(m)
// (the whitened G), and the GLR maximizes l over the onset m = 1..W (a window of the W
// newest innovations). Nested hypotheses (a few columns against all) are told apart by
// the difference of their GLRs, asymptotically chi-square with the number of columns
// dropped (chi_square_quantile). The M(m)^-1 are computed once at construction (the
// matrix work); fit() does the right-hand side only, without allocation.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace tmpc {

/// The last W whitened innovations of consecutive periods (a ring; no allocation in
/// push(); clear() at a gap, which breaks the signatures' alignment in time).
class InnovationWindow {
 public:
  InnovationWindow() = default;
  InnovationWindow(Eigen::Index rows, int window);
  void push(const Eigen::VectorXd& z);
  void clear() { count_ = 0; }
  /// Innovations held (at most window()).
  int size() const { return count_; }
  int window() const { return static_cast<int>(buf_.cols()); }
  /// The innovation `age` periods old (0: the newest), age < size().
  Eigen::Ref<const Eigen::VectorXd> at(int age) const;

 private:
  Eigen::MatrixXd buf_;
  int next_ = 0, count_ = 0;
};

/// Signatures of steps in chosen augmented states under one steady gain.
class StepSignature {
 public:
  StepSignature() = default;
  /// A_a (nx x nx), C (ny x nx), L (nx x ny): the filter; sd (ny, > 0): its steady
  /// innovation deviations; columns: the augmented states a step hits (indices < nx,
  /// none measured: C's column zero); window: W >= 1. Throws std::invalid_argument
  /// naming a size or index that does not fit.
  StepSignature(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L,
                const Eigen::VectorXd& sd, const std::vector<Eigen::Index>& columns, int window);
  /// The same with any step directions E (nx x h, h >= 1, C E = 0: unmeasured states),
  /// e.g. an input's column mapped onto the disturbance states (an actuator's step).
  /// `prior_sd` (h, > 0; empty: none): the deviations of mu's prior for read_step(),
  /// which reads mu along the directions the window determines to within `determined`
  /// (in (0, 1)) of the prior's deviation. Throws std::invalid_argument.
  static StepSignature along(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L,
                             const Eigen::VectorXd& sd, const Eigen::MatrixXd& E, int window,
                             const Eigen::VectorXd& prior_sd = Eigen::VectorXd(), double determined = 0.1);

  struct Fit {
    double statistic = 0.0;  ///< max over the onset of l(m) (0: no innovation yet)
    int onset = 0;           ///< its m: periods since the step's first innovation
  };
  /// The GLR over the window's innovations (newest first, whitened by the same sd);
  /// `step`, when given (sized directions()), receives mu_hat at the best onset.
  Fit fit(const InnovationWindow& z, Eigen::VectorXd* step = nullptr) const;
  /// The step at onset m (1..W), read where the window determines it (a truncated
  /// estimate, as for an ill-posed inverse problem): with S = diag(prior_sd), along the
  /// eigenvectors of S M(m) S whose eigenvalue (the prior's variance over the estimate's)
  /// is at least 1 / determined^2, mu = S (S M(m) S)^+ S b(m) restricted to those; the
  /// other directions are left at zero. Without a prior, M(m)^-1 b(m), fit()'s step.
  /// No allocation; `step` sized directions() (otherwise left alone); zero for an
  /// empty window.
  void read_step(const InnovationWindow& z, int m, Eigen::VectorXd& step) const;
  /// The step's directions (E's columns).
  Eigen::Index directions() const { return b_.size(); }
  /// The unit columns of the first constructor (empty for the second).
  const std::vector<Eigen::Index>& columns() const { return columns_; }
  /// G(k), k = 1..W (whitened), for inspection.
  const Eigen::MatrixXd& signature(int k) const { return G_[static_cast<std::size_t>(k - 1)]; }
  /// The filter's prediction error now from a step E mu whose first innovation was m
  /// periods ago (the newest innovation carries G(m)): Phi^m E, m = 1..W. Adding
  /// Phi^m E mu_hat to the prediction is the GLR's estimate correction (Willsky and
  /// Jones 1976): the filter then continues as if it had known the step from its onset.
  const Eigen::MatrixXd& jump(int m) const { return J_[static_cast<std::size_t>(m - 1)]; }

 private:
  std::vector<Eigen::Index> columns_;
  std::vector<Eigen::MatrixXd> G_;     ///< G(k), k = 1..W
  std::vector<Eigen::MatrixXd> Minv_;  ///< M(m)^-1 (pseudo-inverse where M is singular)
  std::vector<Eigen::MatrixXd> J_;     ///< Phi^m E, m = 1..W
  std::vector<Eigen::MatrixXd> Mread_;  ///< read_step()'s map of b(m) (M(m)^-1 without a prior)
  void build(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L, const Eigen::VectorXd& sd,
             const Eigen::MatrixXd& E, int window, const Eigen::VectorXd& prior_sd, double determined);
  mutable Eigen::VectorXd b_, t_;      ///< fit()'s scratch
};

/// Upper quantile of the chi-square distribution with `dof` degrees of freedom at
/// probability p (0 < p < 1; Wilson and Hilferty's cube-root normal approximation,
/// within 3 % of the table for dof >= 2 at p = 0.999). Throws std::invalid_argument.
double chi_square_quantile(int dof, double p);

}  // namespace tmpc
