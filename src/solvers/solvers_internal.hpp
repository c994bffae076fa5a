// Internal solver classes behind make_solver().
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "active_set_polish.hpp"
#include "dense_admm.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc::detail {

/// Checks x0 (size, finiteness); on failure fills `res` with InvalidInput.
bool valid_state(const Eigen::VectorXd& x0, int n, SolveResult& res);

class AdmmPolytope final : public QpSolver {
 public:
  AdmmPolytope(const ParametricQp& qp, int M, int m, int N, int n, const SolverOptions& opt);
  const SolveResult& solve(const Eigen::VectorXd& x0) override;
  void reset() override { admm_.reset(); }
  const char* name() const override { return "admm"; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }
  double rho() const { return admm_.rho(); }

 private:
  ParametricQp qp_;
  SolverOptions opt_;
  DenseAdmm admm_;
  Eigen::VectorXd f_, lo_, hi_;
  SolveResult res_;
};

/// Algorithm 4.3 as written (E2 fixed): variables x_hat, u_hat, scaled dual lambda
/// of x_hat = P u_hat + Q x0; u-step (4.25)-(4.26): unconstrained minimizer of the
/// dense H1 = P'rho P + 2 W_u, then clipped (exact only for a diagonal H1: E3);
/// x-step (4.27)-(4.28) likewise with H2 = rho + 2 W_x; symmetric dual steps r, s;
/// Nesterov on (x_hat, lambda) with the restart of Algorithm 4.2; stop when
/// ||Gamma||_inf = ||x_hat - P u_hat - Q x0||_inf <= epsilon.
class AdmmThesis final : public QpSolver {
 public:
  AdmmThesis(const MpcQpData& d, const ParametricQp& qp, const SolverOptions& opt);
  const SolveResult& solve(const Eigen::VectorXd& x0) override;
  void reset() override { have_previous_ = false; }
  const char* name() const override { return "admm-thesis"; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }

 private:
  int n_, m_, N_, M_;
  Eigen::MatrixXd P_, Pt_, Q_;
  Eigen::MatrixXd H1_inv_;        // (P'rho P + 2 W_u)^-1
  Eigen::MatrixXd H2_last_inv_;   // (rho I + 2 L)^-1 (terminal block)
  Eigen::VectorXd H2_diag_inv_;   // (rho + 2 Sigma_rho)^-1, stage blocks (diagonal weights)
  Eigen::MatrixXd Wx_, Wu_;
  ParametricQp qp_;
  SolverOptions opt_;
  double rho_;
  bool have_previous_ = false;
  int nd_ = 0;                    // offset-free form: the boxes move with d (mpc_qp.hpp)
  Eigen::MatrixXd Tx_, Tu_, Phi_;
  Eigen::VectorXd xlo0_, xhi0_, ulo0_, uhi0_, xs_, us_;
  Eigen::VectorXd xlo_, xhi_, ulo_, uhi_;
  Eigen::VectorXd x_, u_, lam_, xe_, lame_, xprev_, lamprev_, Qx0_, Pu_, g_, t_n_, t_u_, f_;
  SolveResult res_;
};

/// Constrained-zonotope formulation (4.46): zeta = (zeta_u, zeta_x) with
/// x_hat = c_x + G_x zeta_x, u_hat = c_u + G_u zeta_u, the dynamics
/// G_x zeta_x - P G_u zeta_u = P c_u - c_x + Q x0, the sets' own equalities
/// F_u zeta_u = f_u, F_x zeta_x = f_x, and unit boxes on zeta; solved by the exact
/// ADMM machinery (the Hessian G'WG is singular when the sets have more generators
/// than dimensions; the proximal sigma keeps the step well posed).
class AdmmCz final : public QpSolver {
 public:
  AdmmCz(const MpcQpData& d, const ParametricQp& polytope, const SolverOptions& opt);
  const SolveResult& solve(const Eigen::VectorXd& x0) override;
  void reset() override { admm_->reset(); }
  const char* name() const override { return "cz"; }
  const ParametricQp& problem() const override { return polytope_; }
  const SolverOptions& options() const override { return opt_; }
  /// The QP in zeta coordinates (for KKT checks of the CZ problem itself).
  const ParametricQp& cz_problem() const { return cz_; }
  const Eigen::VectorXd& zeta() const { return inner_.z; }

 private:
  ParametricQp polytope_, cz_;
  SolverOptions opt_;
  Eigen::MatrixXd Gu_full_;   // u_hat = cu_full_ + Gu_full_ zeta
  Eigen::VectorXd cu_full_;
  std::unique_ptr<DenseAdmm> admm_;
  Eigen::VectorXd f_, lo_, hi_, fp_, tz_, lop_, hip_;
  int nd_ = 0, n_ = 0, M_ = 0, m_ = 0;
  Eigen::MatrixXd Tu_;
  Eigen::VectorXd us_;
  SolveResult inner_, res_;
};

/// Dense primal-dual interior point (Mehrotra predictor-corrector) on
/// lo <= A z <= hi, then an active-set polish; KKT residuals below 1e-9.
class ReferenceQp final : public QpSolver {
 public:
  ReferenceQp(const ParametricQp& qp, const SolverOptions& opt);
  const SolveResult& solve(const Eigen::VectorXd& x0) override;
  void reset() override {}
  const char* name() const override { return "reference"; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }

 private:
  bool polish();
  bool polish_with(bool primal_activity);
  ParametricQp qp_;
  SolverOptions opt_;
  int nz_, nc_;
  Eigen::VectorXd f_, lo_, hi_;
  // IPM over G z <= h: rows 0..nc-1 are "a_i'z <= hi_i", rows nc..2nc-1 are "-a_i'z <= -lo_i".
  Eigen::VectorXd z_, lam_, s_, dz_, dlam_, ds_, rd_, rp_, rc_, w_, t2_, Gz_, h_;
  std::vector<char> active_row_;  // finite bound
  Eigen::MatrixXd Mred_, AtW_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  ActiveSetPolish polish_;
  SolveResult res_;
};

}  // namespace tmpc::detail
