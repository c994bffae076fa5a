// "admm": the exact ADMM on the polytope formulation (condensed, z = u_hat).
#include "solvers_internal.hpp"

namespace tmpc::detail {

namespace {
/// Rows to shift for the warm start: the inputs and the stages (twice in the softened
/// form: upper and lower rows); the slacks and their rows stay.
std::vector<ShiftSegment> row_segments(const ParametricQp& qp, int M, int m, int N, int n) {
  std::vector<ShiftSegment> rows{{0, m, M}, {M * m, n, N}};
  if (qp.slacks > 0) rows.push_back({M * m + N * n, n, N});
  return rows;
}
}  // namespace

AdmmPolytope::AdmmPolytope(const ParametricQp& qp, int M, int m, int N, int n, const SolverOptions& opt)
    : qp_(qp),
      opt_(opt),
      admm_(qp.H, qp.A, qp.lo0, qp.hi0, opt, {{0, m, M}}, row_segments(qp, M, m, N, n)) {
  f_.resize(qp.nz());
  lo_.resize(qp.nc());
  hi_.resize(qp.nc());
  res_.z.resize(qp.nz());
  res_.y.resize(qp.nc());
}

const SolveResult& AdmmPolytope::solve(const Eigen::VectorXd& x0) {
  if (!valid_state(x0, qp_.nx(), res_)) return res_;
  qp_.instance_into(x0, f_, lo_, hi_);
  admm_.solve(f_, lo_, hi_, res_);
  return res_;
}

}  // namespace tmpc::detail
