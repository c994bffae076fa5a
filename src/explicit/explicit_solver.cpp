// The explicit law as a QpSolver (point location + affine law, no iterations).
#include "tmpc/explicit/explicit_solver.hpp"

#include <chrono>

#include "tmpc/qp/parametric_qp.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

namespace {

class ExplicitSolver final : public QpSolver {
 public:
  ExplicitSolver(const ControllerArtifact& a, ExplicitLaw law, Locator locator, int threads)
      : law_(std::move(law)),
        qp_(ParametricQp::from_mpc(build_mpc_qp(a.A, a.B, a.Sigma_rho, a.Sigma_lambda, a.L, a.x_bar, a.u_bar,
                                                law_.N, law_.M))),
        scan_(law_.table, threads),
        locator_(locator) {
    res_.z = Eigen::VectorXd::Zero(law_.nz);
    res_.y = Eigen::VectorXd::Zero(qp_.nc());
    hz_ = Eigen::VectorXd::Zero(law_.nz);
    fx_ = Eigen::VectorXd::Zero(law_.nz);
    opt_.warm_start = false;
  }

  const SolveResult& solve(const Eigen::VectorXd& x0) override {
    const auto t0 = std::chrono::steady_clock::now();
    res_.iterations = 0;
    res_.restarts = 0;
    res_.primal_residual = res_.dual_residual = 0.0;
    if (x0.size() != law_.n || !x0.allFinite()) {
      res_.status = SolveStatus::InvalidInput;
      res_.solve_us = 0.0;
      return res_;
    }
    const int region = locator_ == Locator::Tree ? law_.tree.locate(law_.table, x0) : scan_.locate(x0);
    last_region_ = region;
    if (region < 0) {
      res_.status = SolveStatus::Infeasible;
      res_.z.setZero();
      res_.objective = 0.0;
    } else {
      law_.evaluate(region, x0, res_.z);
      hz_.noalias() = qp_.H * res_.z;
      fx_ = qp_.f0;
      fx_.noalias() += qp_.F * x0;
      res_.objective = 0.5 * res_.z.dot(hz_) + res_.z.dot(fx_);
      res_.status = SolveStatus::Converged;
    }
    res_.solve_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    return res_;
  }
  void reset() override {}
  const char* name() const override { return "explicit"; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }

 private:
  ExplicitLaw law_;
  ParametricQp qp_;
  RegionScan scan_;
  Locator locator_;
  SolverOptions opt_;
  SolveResult res_;
  Eigen::VectorXd hz_, fx_;
  int last_region_ = -1;
};

}  // namespace

std::unique_ptr<QpSolver> make_explicit_solver(const ControllerArtifact& a, ExplicitLaw law, Locator locator,
                                               int scan_threads) {
  if (law.n != a.n || law.nz != a.m * law.M) {
    throw std::invalid_argument("explicit law: sizes (n " + std::to_string(law.n) + ", nz " + std::to_string(law.nz) +
                                ") disagree with the artifact (n " + std::to_string(a.n) + ", m " +
                                std::to_string(a.m) + ")");
  }
  return std::make_unique<ExplicitSolver>(a, std::move(law), locator, scan_threads);
}

}  // namespace tmpc
