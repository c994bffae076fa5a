// Theorem 3.1 as an SDP, with independent checks of the returned gain.
#include "tmpc/synthesis/lmi_gain.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

const char* to_string(LmiForm f) { return f == LmiForm::Thesis ? "thesis" : "robust"; }

namespace {

Eigen::MatrixXd sqrt_psd(const Eigen::MatrixXd& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (m + m.transpose()));
  return es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace

LmiGainResult solve_lmi_gain(const LmiGainProblem& p) {
  const int n = static_cast<int>(p.B.rows());
  const int m = static_cast<int>(p.B.cols());
  const int r = static_cast<int>(p.Hw.cols());
  LmiProblem lmi;
  const AffineMatrix W = lmi.add_symmetric(n);
  const AffineMatrix Y = lmi.add_matrix(m, n);
  const int kappa = lmi.add_scalar();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);

  // C'C = Sigma_rho, D'D = Sigma_lambda, C'D = 0.
  Eigen::MatrixXd Cq = Eigen::MatrixXd::Zero(n + m, n), Dq = Eigen::MatrixXd::Zero(n + m, m);
  Cq.topRows(n) = sqrt_psd(p.Q);
  Dq.bottomRows(m) = sqrt_psd(p.R);

  // W >= w_floor I: without a floor the objective of E5 is unbounded below in the
  // thesis form (every constraint but the Riccati I-block is homogeneous in W and
  // that block only relaxes as W shrinks), so the solution would sit at the margin.
  lmi.require_psd(W - AffineMatrix::constant(std::max(p.margin, p.w_floor) * I), "W >= w_floor I");
  AffineMatrix kI(n, n);
  for (int i = 0; i < n; ++i) kI.add_term(kappa, i, i, 1.0);
  lmi.require_psd(kI - W, "kappa I - W >= 0 (E5)");
  lmi.set_objective(kappa, 1.0);

  AffineMatrix zeta;
  if (p.form == LmiForm::Thesis) {
    zeta = lmi.add_matrix(r, 1);
    // ||zeta||_2 <= 1 (3.24)
    lmi.require_psd(LmiProblem::symmetric_blocks({{AffineMatrix::constant(Eigen::MatrixXd::Ones(1, 1))},
                                                  {zeta, AffineMatrix::constant(Eigen::MatrixXd::Identity(r, r))}}),
                    "[1 zeta'; zeta I] >= 0 (3.24)");
  }
  const AffineMatrix CWDY = Cq * W + Dq * Y;
  for (std::size_t i = 0; i < p.A.size(); ++i) {
    const AffineMatrix AWBY = p.A[i] * W + p.B * Y;
    const std::string v = " vertex " + std::to_string(i);
    // (3.21), negated: [W  (CW+DY)'  (AW+BY)'; CW+DY  I  0; AW+BY  0  W] > 0 (off-diagonal signs
    // flip together, which leaves the inertia unchanged).
    AffineMatrix ric = LmiProblem::symmetric_blocks(
        {{W}, {CWDY, AffineMatrix::constant(Eigen::MatrixXd::Identity(n + m, n + m))}, {AWBY, AffineMatrix(), W}});
    lmi.require_psd(ric - AffineMatrix::constant(p.margin * Eigen::MatrixXd::Identity(ric.rows(), ric.rows())),
                    "Riccati (3.21)" + v);
    if (p.form == LmiForm::Thesis) {
      lmi.require_psd(LmiProblem::symmetric_blocks({{W * p.lambda},
                                                    {AffineMatrix(), AffineMatrix::constant(Eigen::MatrixXd::Constant(1, 1, 1.0 - p.lambda))},
                                                    {AWBY, p.Hw * zeta, W}}),
                      "invariance (3.15)" + v);
    } else {
      lmi.require_psd(
          LmiProblem::symmetric_blocks({{W * p.lambda},
                                        {AffineMatrix(), AffineMatrix::constant(((1.0 - p.lambda) / r) * Eigen::MatrixXd::Identity(r, r))},
                                        {AWBY, AffineMatrix::constant(p.Hw), W}}),
          "invariance, robust (E4)" + v);
    }
  }
  for (int j = 0; j < m; ++j) {
    AffineMatrix Yj(1, n);
    for (const auto& [var, entries] : Y.terms()) {
      for (const AffineMatrix::Entry& e : entries) {
        if (e.i == j) Yj.add_term(var, 0, e.j, e.v);
      }
    }
    lmi.require_psd(LmiProblem::symmetric_blocks({{AffineMatrix::constant(Eigen::MatrixXd::Constant(1, 1, p.u_max(j) * p.u_max(j)))},
                                                  {Yj.transpose(), W}}),
                    "input bound (3.19) channel " + std::to_string(j));
  }

  LmiGainResult out;
  out.lambda = p.lambda;
  out.variables = lmi.variables();
  const SdpResult sdp = lmi.solve();
  out.status = sdp.status;
  out.message = sdp.message;
  out.seconds = sdp.seconds;
  if (!sdp.usable()) return out;

  // Independent checks (not the solver's word).
  const Eigen::MatrixXd Wv = W.value(sdp.y);
  const Eigen::MatrixXd Yv = Y.value(sdp.y);
  out.W = 0.5 * (Wv + Wv.transpose());
  out.K = Yv * out.W.inverse();
  out.L = out.W.inverse();
  out.kappa = sdp.y(kappa);
  if (p.form == LmiForm::Thesis) out.zeta = zeta.value(sdp.y);
  out.block_min_eigenvalue = lmi.block_min_eigenvalues(sdp.y);
  out.block_names = lmi.block_names();
  out.worst_block_eigenvalue = 1e300;
  for (double e : out.block_min_eigenvalue) out.worst_block_eigenvalue = std::min(out.worst_block_eigenvalue, e);
  double worst_rho = 0.0;
  for (const Eigen::MatrixXd& A : p.A) {
    out.vertex_spectral_radius.push_back(spectral_radius(A + p.B * out.K));
    worst_rho = std::max(worst_rho, out.vertex_spectral_radius.back());
  }
  out.input_bound_ratio = 0.0;
  for (int j = 0; j < m; ++j) {
    const double reach = std::sqrt(std::max(0.0, (out.K.row(j) * out.W * out.K.row(j).transpose())(0, 0)));
    out.input_bound_ratio = std::max(out.input_bound_ratio, reach / p.u_max(j));
  }
  std::ostringstream why;
  // The solver's own tolerance is about 1e-7 relative; allow that on the blocks.
  const double tol = -1e-6 * std::max(1.0, out.W.norm());
  if (out.worst_block_eigenvalue < tol) why << "an LMI block has eigenvalue " << out.worst_block_eigenvalue << "; ";
  if (worst_rho >= 1.0) why << "A_i + B K has spectral radius " << worst_rho << "; ";
  if (out.input_bound_ratio > 1.0 + 1e-6) why << "input bound exceeded by factor " << out.input_bound_ratio << "; ";
  out.feasible = why.str().empty();
  if (!out.feasible) out.message = "solution rejected by the independent check: " + why.str() + "solver said: " + out.message;
  return out;
}

LmiGainResult solve_lmi_gain_line_search(LmiGainProblem p, int steps) {
  // Feasibility is monotone in lambda (a larger lambda relaxes (3.15)): bisect for the
  // smallest feasible lambda in (lo, hi], starting from hi = 0.999.
  double lo = 0.5, hi = 0.999;
  p.lambda = hi;
  LmiGainResult best = solve_lmi_gain(p);
  if (!best.feasible) return best;
  for (int s = 0; s < steps; ++s) {
    p.lambda = 0.5 * (lo + hi);
    LmiGainResult r = solve_lmi_gain(p);
    if (r.feasible) {
      hi = p.lambda;
      best = std::move(r);
    } else {
      lo = p.lambda;
    }
  }
  return best;
}

}  // namespace tmpc
