// QpSolver adapters of the GPU ADMM (see cuda_qp_solver.hpp).
#include "cuda_qp_solver.hpp"

#include <chrono>
#include <stdexcept>
#include <string>

#include "admm_device.hpp"
#include "tmpc/solvers/gpu_problem.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {

namespace {

double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

SolveStatus status_of(int s) {
  switch (s) {
    case gpu::kConverged: return SolveStatus::Converged;
    case gpu::kMaxIterations: return SolveStatus::MaxIterations;
    case gpu::kTimeBudget: return SolveStatus::TimeBudget;
    case gpu::kInvalidInput: return SolveStatus::InvalidInput;
    case gpu::kInfeasible: return SolveStatus::Infeasible;
    default: return SolveStatus::NumericalFailure;
  }
}

/// Objective 1/2 z'Hz + f'z in double on the host (the device returns z only).
double objective(const ParametricQp& qp, const Eigen::VectorXd& x0, const Eigen::VectorXd& z, Eigen::VectorXd& f) {
  f = qp.f0;
  f.noalias() += qp.F * x0;
  return 0.5 * z.dot(qp.H * z) + f.dot(z);
}

class CudaQpSolver final : public QpSolver {
 public:
  CudaQpSolver(const MpcQpData& d, const SolverOptions& o, int variant, const char* name)
      : qp_(ParametricQp::from_mpc(d)),
        opt_(o),
        name_(name),
        dev_(make_gpu_problem(d, o), make_gpu_settings(o, variant), cuda::DeviceOptions{}) {
    if (!dev_.ok()) throw std::runtime_error(std::string(name) + ": " + dev_.error());
    x0f_.resize(static_cast<std::size_t>(qp_.nx()));
    res_.z.setZero(qp_.nz());
    res_.y.setZero(qp_.nc());
    f_.resize(qp_.nz());
  }

  const SolveResult& solve(const Eigen::VectorXd& x0) override {
    const double t0 = now_us();
    if (x0.size() != qp_.nx() || !x0.allFinite()) {
      res_.status = SolveStatus::InvalidInput;
      res_.iterations = 0;
      res_.solve_us = 0.0;
      return res_;
    }
    for (int i = 0; i < qp_.nx(); ++i) x0f_[static_cast<std::size_t>(i)] = static_cast<float>(x0(i));
    if (!dev_.start(x0f_.data()) || !dev_.wait()) {
      res_.status = SolveStatus::NumericalFailure;  // dev_.error() says why; the runtime falls back
      res_.iterations = 0;
      res_.solve_us = now_us() - t0;
      return res_;
    }
    const gpu::AdmmOutcome& g = dev_.outcome();
    res_.status = status_of(g.status);
    res_.iterations = g.iterations;
    res_.restarts = g.restarts;
    res_.primal_residual = g.primal_residual;
    res_.dual_residual = g.dual_residual;
    const float* z = dev_.z();
    for (int i = 0; i < qp_.nz(); ++i) res_.z(i) = z[i];
    res_.objective = objective(qp_, x0, res_.z, f_);
    res_.solve_us = now_us() - t0;
    return res_;
  }
  void reset() override { dev_.reset(); }
  const char* name() const override { return name_; }
  const ParametricQp& problem() const override { return qp_; }
  const SolverOptions& options() const override { return opt_; }

 private:
  ParametricQp qp_;
  SolverOptions opt_;
  const char* name_;
  cuda::AdmmDevice dev_;
  std::vector<float> x0f_;
  Eigen::VectorXd f_;
  SolveResult res_;
};

std::vector<SolveResult> batch(const MpcQpData& d, const SolverOptions& o, const std::vector<Eigen::VectorXd>& x0s,
                               int variant, const char* name) {
  const ParametricQp qp = ParametricQp::from_mpc(d);
  const int B = static_cast<int>(x0s.size());
  std::vector<SolveResult> out(x0s.size());
  if (B == 0) return out;
  cuda::DeviceOptions dopt;
  dopt.max_batch = B;
  dopt.cublas_path = false;
  cuda::AdmmDevice dev(make_gpu_problem(d, o), make_gpu_settings(o, variant), dopt);
  if (!dev.ok()) throw std::runtime_error(std::string(name) + ": " + dev.error());
  std::vector<float> x(static_cast<std::size_t>(B) * qp.nx()), z(static_cast<std::size_t>(B) * qp.nz());
  for (int b = 0; b < B; ++b) {
    if (x0s[static_cast<std::size_t>(b)].size() != qp.nx())
      throw std::invalid_argument(std::string(name) + ": state " + std::to_string(b) + " has the wrong size");
    for (int i = 0; i < qp.nx(); ++i) x[static_cast<std::size_t>(b) * qp.nx() + i] = static_cast<float>(x0s[static_cast<std::size_t>(b)](i));
  }
  std::vector<gpu::AdmmOutcome> g(static_cast<std::size_t>(B));
  const double t0 = now_us();
  if (!dev.solve_batch(x.data(), B, g.data(), z.data(), false)) throw std::runtime_error(std::string(name) + ": " + dev.error());
  const double per_qp = (now_us() - t0) / B;
  Eigen::VectorXd f(qp.nz());
  for (int b = 0; b < B; ++b) {
    SolveResult& r = out[static_cast<std::size_t>(b)];
    const gpu::AdmmOutcome& o_b = g[static_cast<std::size_t>(b)];
    const Eigen::VectorXd& x0 = x0s[static_cast<std::size_t>(b)];
    r.status = x0.allFinite() ? status_of(o_b.status) : SolveStatus::InvalidInput;
    r.iterations = o_b.iterations;
    r.restarts = o_b.restarts;
    r.primal_residual = o_b.primal_residual;
    r.dual_residual = o_b.dual_residual;
    r.z.resize(qp.nz());
    for (int i = 0; i < qp.nz(); ++i) r.z(i) = z[static_cast<std::size_t>(b) * qp.nz() + i];
    r.y.setZero(qp.nc());
    r.objective = objective(qp, x0, r.z, f);
    r.solve_us = per_qp;  // the launch's time shared out
  }
  return out;
}

std::unique_ptr<QpSolver> make_exact(const MpcQpData& d, const SolverOptions& o) {
  return std::make_unique<CudaQpSolver>(d, o, gpu::kExact, "admm-cuda");
}
void thesis_needs_fixed_sets(const MpcQpData& d) {
  // The thesis kernel keeps its boxes on the device; the offset-free form moves them
  // every period (mpc_qp.hpp), which only the exact variant does (through E).
  if (d.disturbances() > 0)
    throw std::invalid_argument("admm-cuda-thesis: no offset-free form (its sets are fixed on the device); use admm-cuda");
  if (d.rate_weighted())
    throw std::invalid_argument("admm-cuda-thesis: no input-rate weight (its u-step is built from W_u alone); use admm-cuda");
}
std::unique_ptr<QpSolver> make_thesis(const MpcQpData& d, const SolverOptions& o) {
  thesis_needs_fixed_sets(d);
  return std::make_unique<CudaQpSolver>(d, o, gpu::kThesis, "admm-cuda-thesis");
}
std::vector<SolveResult> batch_exact(const MpcQpData& d, const SolverOptions& o, const std::vector<Eigen::VectorXd>& x0s) {
  return batch(d, o, x0s, gpu::kExact, "admm-cuda");
}
std::vector<SolveResult> batch_thesis(const MpcQpData& d, const SolverOptions& o, const std::vector<Eigen::VectorXd>& x0s) {
  thesis_needs_fixed_sets(d);
  return batch(d, o, x0s, gpu::kThesis, "admm-cuda-thesis");
}

}  // namespace

void register_cuda_solvers() {
  register_solver("admm-cuda", make_exact, batch_exact);
  register_solver("admm-cuda-thesis", make_thesis, batch_thesis);
}

}  // namespace tmpc
