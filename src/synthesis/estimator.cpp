// Kalman filter of the offset-free error model and the output-feedback tube (see
// estimator.hpp).
#include "tmpc/synthesis/estimator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "tmpc/synthesis/lqr.hpp"
#include "tmpc/synthesis/rpi.hpp"

namespace tmpc {

KalmanDesign kalman_model(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                          const Eigen::MatrixXd& E_c, const std::vector<int>& measured_rows) {
  const Eigen::Index n = A.rows(), nd = D.cols(), nc = E_c.cols(), na = n + nd + nc;
  if (A.cols() != n || B.rows() != n || D.rows() != n || (nc > 0 && E_c.rows() != n) || measured_rows.empty()) {
    throw std::invalid_argument("kalman_model: A must be n x n with B, D, E_c of n rows and at least one measured row");
  }
  KalmanDesign k;
  k.p = static_cast<int>(n);
  k.measured_rows = measured_rows;
  k.E_c = nc > 0 ? E_c : Eigen::MatrixXd::Zero(n, 0);
  k.A_a = Eigen::MatrixXd::Identity(na, na);
  k.A_a.topLeftCorner(n, n) = A;
  k.A_a.block(0, n, n, nd) = D;
  if (nc > 0) k.A_a.block(0, n + nd, n, nc) = E_c;
  k.B_a = Eigen::MatrixXd::Zero(na, B.cols());
  k.B_a.topRows(n) = B;
  k.C = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(measured_rows.size()), na);
  for (std::size_t i = 0; i < measured_rows.size(); ++i) {
    const int r = measured_rows[i];
    if (r < 0 || r >= n) throw std::invalid_argument("kalman_model: measured row " + std::to_string(r) + " out of range");
    k.C(static_cast<Eigen::Index>(i), r) = 1.0;
  }
  return k;
}

KalmanDesign design_kalman(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                           const Eigen::MatrixXd& E_c, const std::vector<int>& measured_rows,
                           const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  return redesign_kalman(kalman_model(A, B, D, E_c, measured_rows), Q, R);
}

KalmanDesign redesign_kalman(const KalmanDesign& model, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  KalmanDesign k = model;
  const Eigen::Index na = k.A_a.rows(), ny = k.C.rows();
  if (Q.rows() != na || Q.cols() != na || R.rows() != ny || R.cols() != ny) {
    throw std::invalid_argument("design_kalman: Q must be " + std::to_string(na) + " square and R " +
                                std::to_string(ny) + " square");
  }
  k.Q = Q;
  k.R = R;
  // The filter Riccati equation is the LQR one of the dual pair (A_a', C').
  const LqrResult dual = solve_dlqr(k.A_a.transpose(), k.C.transpose(), Q, R);
  k.P = 0.5 * (dual.P + dual.P.transpose());
  const Eigen::MatrixXd S = k.C * k.P * k.C.transpose() + R;
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) throw std::runtime_error("Kalman filter: C P C' + R is not positive definite");
  k.L = llt.solve(k.C * k.P).transpose();  // P C' S^-1 (S, P symmetric)
  const Eigen::MatrixXd Se = (Eigen::MatrixXd::Identity(na, na) - k.L * k.C) * k.A_a;
  k.spectral_radius = spectral_radius(Se);
  if (!(k.spectral_radius < 1.0) || !k.L.allFinite()) {
    throw std::runtime_error("Kalman filter: the estimation error does not converge (spectral radius " +
                             std::to_string(k.spectral_radius) + "); the disturbance model is not detectable from the measured states");
  }
  return k;
}

namespace {
/// The standard deviations on a covariance's diagonal.
Eigen::VectorXd diagonal_sd(const Eigen::MatrixXd& S) { return S.diagonal().cwiseMax(0.0).cwiseSqrt(); }
}  // namespace

namespace {
/// C's column of each row where C selects states (one 1 a row, distinct columns, zeros
/// elsewhere: kalman_model()'s measurement map); empty otherwise.
std::vector<Eigen::Index> selected_columns(const Eigen::MatrixXd& C) {
  std::vector<Eigen::Index> cols;
  std::vector<char> taken(static_cast<std::size_t>(C.cols()), 0);
  for (Eigen::Index i = 0; i < C.rows(); ++i) {
    Eigen::Index j = 0;
    C.row(i).cwiseAbs().maxCoeff(&j);
    if (C(i, j) != 1.0 || C.row(i).cwiseAbs().sum() != 1.0 || taken[static_cast<std::size_t>(j)] != 0) {
      return {};
    }
    taken[static_cast<std::size_t>(j)] = 1;
    cols.push_back(j);
  }
  return cols;
}
}  // namespace

std::vector<Eigen::MatrixXd> start_gains(const KalmanDesign& k, const Eigen::MatrixXd& P0, double tolerance, int max_steps,
                                         std::vector<Eigen::VectorXd>* innovation_sds) {
  const Eigen::Index na = k.A_a.rows(), ny = k.C.rows();
  if (P0.rows() != na || P0.cols() != na || k.Q.rows() != na || k.R.rows() != ny || k.L.rows() != na || k.L.cols() != ny) {
    throw std::invalid_argument("start_gains: P0 and Q must be " + std::to_string(na) + " square, R " + std::to_string(ny) +
                                " square and L " + std::to_string(na) + "x" + std::to_string(ny));
  }
  const double scale = k.L.cwiseAbs().maxCoeff();
  // A selecting C (the filters of this project) is applied by indexing: the same numbers
  // as the products with its ones and zeros, without their cost. The buffers are reused
  // across steps (a schedule runs to 2000 steps, four at each controller's construction).
  const std::vector<Eigen::Index> sel = selected_columns(k.C);
  const bool selects = !sel.empty();
  std::vector<Eigen::MatrixXd> gains;
  Eigen::MatrixXd P = 0.5 * (P0 + P0.transpose());
  Eigen::MatrixXd S(ny, ny), CP(ny, na), M(na, na), MP(na, na), Pp(na, na), LR(na, ny), AP(na, na);
  Eigen::LLT<Eigen::MatrixXd> llt(ny);
  if (innovation_sds != nullptr) innovation_sds->clear();
  for (int step = 0; step < max_steps; ++step) {
    if (selects) {
      CP = P(sel, Eigen::all);
      S = P(sel, sel) + k.R;
    } else {
      CP.noalias() = k.C * P;
      S.noalias() = CP * k.C.transpose();
      S += k.R;
    }
    if (innovation_sds != nullptr) innovation_sds->push_back(diagonal_sd(S));
    llt.compute(S);
    if (llt.info() != Eigen::Success) throw std::runtime_error("Kalman filter start: C P C' + R is not positive definite at step " + std::to_string(step));
    Eigen::MatrixXd L = llt.solve(CP).transpose();
    if (!L.allFinite()) throw std::runtime_error("Kalman filter start: a non-finite gain at step " + std::to_string(step));
    const bool done = (L - k.L).cwiseAbs().maxCoeff() <= tolerance * scale;
    gains.push_back(std::move(L));
    if (done) break;
    const Eigen::MatrixXd& Lk = gains.back();
    // P+ = (I - L C) P (I - L C)' + L R L' (Joseph's form), P = A_a P+ A_a' + Q.
    if (selects) {
      M.setIdentity();
      for (Eigen::Index j = 0; j < ny; ++j) M.col(sel[static_cast<std::size_t>(j)]) -= Lk.col(j);
    } else {
      M.noalias() = -Lk * k.C;
      M.diagonal().array() += 1.0;
    }
    MP.noalias() = M * P;
    Pp.noalias() = MP * M.transpose();
    LR.noalias() = Lk * k.R;
    Pp.noalias() += LR * Lk.transpose();
    AP.noalias() = k.A_a * Pp;
    P.noalias() = AP * k.A_a.transpose();
    P += k.Q;
    P = 0.5 * (P + P.transpose());
  }
  return gains;
}

Eigen::MatrixXd start_covariance(const KalmanDesign& k, Eigen::Index nd, double force_std, double residual_std,
                                 double state_noise) {
  const Eigen::Index na = k.A_a.rows(), p = k.p, nc = na - p - nd;
  if (k.P.rows() != na || k.R.rows() != k.C.rows() || nd < 0 || nc < 0 || !(force_std >= 0.0) ||
      !(residual_std >= 0.0) || !(state_noise >= 0.0)) {
    throw std::invalid_argument("start_covariance: needs the steady P (" + std::to_string(na) + " square), R, nd in [0, " +
                                std::to_string(na - p) + "] and standard deviations >= 0");
  }
  Eigen::MatrixXd P0 = k.P;
  if (state_noise > 0.0) {
    const Eigen::VectorXd steady = k.P.diagonal().head(p);
    P0.topRows(p).setZero();
    P0.leftCols(p).setZero();
    for (Eigen::Index i = 0; i < p; ++i) P0(i, i) = steady(i);
    for (std::size_t j = 0; j < k.measured_rows.size(); ++j) {
      const Eigen::Index r = k.measured_rows[j], jj = static_cast<Eigen::Index>(j);
      P0(r, r) = state_noise * state_noise * k.R(jj, jj);
    }
  }
  auto replace = [&](Eigen::Index first, Eigen::Index count, double std_dev) {
    if (std_dev <= 0.0 || count == 0) return;  // kept: the steady block
    std::vector<Eigen::Index> states(static_cast<std::size_t>(count));
    for (Eigen::Index i = 0; i < count; ++i) states[static_cast<std::size_t>(i)] = first + i;
    open_states(P0, states, std_dev);
  };
  replace(p, nd, force_std);
  replace(p + nd, nc, residual_std);
  return P0;
}

void open_states(Eigen::MatrixXd& P, const std::vector<Eigen::Index>& states, double std_dev) {
  if (!(std_dev > 0.0) || !std::isfinite(std_dev)) {
    throw std::invalid_argument("open_states: the standard deviation must be finite and > 0, not " + std::to_string(std_dev));
  }
  for (const Eigen::Index i : states) {
    if (i < 0 || i >= P.rows() || P.rows() != P.cols()) {
      throw std::invalid_argument("open_states: state " + std::to_string(i) + " is outside the " +
                                  std::to_string(P.rows()) + " x " + std::to_string(P.cols()) + " covariance");
    }
  }
  for (const Eigen::Index i : states) {
    P.row(i).setZero();
    P.col(i).setZero();
  }
  for (const Eigen::Index i : states) P(i, i) = std_dev * std_dev;
}

namespace {

/// RPI set of e+ = S e + w, w in W, over the given loops (the first nominal): the
/// robust LPV form when there are vertices.
Zonotope rpi(const std::vector<Eigen::MatrixXd>& loops, const Zonotope& W, double lambda) {
  RpiSettings rs;
  rs.lambda = lambda;
  if (loops.size() <= 1) return rpi_lti(loops.front(), W, rs).Z;
  return rpi_lpv_robust(loops.front(), std::vector<Eigen::MatrixXd>(loops.begin() + 1, loops.end()), W, rs).Z;
}

/// A centred box of the given half-widths as a zonotope (a floor keeps it full-dimensional,
/// as the RPI formula's H_w^-1 needs).
Zonotope box_zonotope(const Eigen::VectorXd& r) {
  const double floor = 1e-12 * std::max(1.0, r.maxCoeff());
  return Zonotope(Eigen::VectorXd::Zero(r.size()), Eigen::MatrixXd(r.cwiseMax(floor).asDiagonal()));
}

Eigen::VectorXd abs_row_sums(const Eigen::MatrixXd& M) { return M.cwiseAbs().rowwise().sum(); }

}  // namespace

OutputFeedbackTube output_feedback_tube(const KalmanDesign& k, const std::vector<Eigen::MatrixXd>& closed_loops,
                                        const Eigen::MatrixXd& K, const Eigen::VectorXd& W_a,
                                        const Eigen::VectorXd& V, const Box& X, const Box& U, double rpi_lambda) {
  const Eigen::Index na = k.A_a.rows(), ny = k.C.rows(), n = K.cols(), p = k.p;
  if (W_a.size() != na || V.size() != ny || closed_loops.empty() || X.dim() != n || U.dim() != K.rows() || p > n) {
    throw std::invalid_argument("output_feedback_tube: W_a needs " + std::to_string(na) + " entries and V " +
                                std::to_string(ny));
  }
  OutputFeedbackTube t;
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(na, na) - k.L * k.C;
  const Eigen::MatrixXd Se = M * k.A_a;
  RpiSettings rs;
  rs.lambda = rpi_lambda;
  const Eigen::VectorXd floor_wa = W_a.cwiseMax(1e-12);
  const RpiResult ew = rpi_lti(Se, Zonotope(Eigen::VectorXd::Zero(na), M * floor_wa.asDiagonal()), rs);
  const RpiResult ev = rpi_lti(Se, Zonotope(Eigen::VectorXd::Zero(na), -k.L * V.asDiagonal()), rs);
  t.E_W = ew.Z;
  t.E_V = ev.Z;
  t.j_estimation = std::max(ew.j, ev.j);
  Eigen::VectorXd ex_w = Eigen::VectorXd::Zero(n), ex_v = Eigen::VectorXd::Zero(n);
  ex_w.head(p) = t.E_W.radius().head(p);
  ex_v.head(p) = t.E_V.radius().head(p);
  t.e_x_radius = ex_w + ex_v;
  // The control error's disturbance: the x rows of the correction L (y - C xi^-).
  Eigen::MatrixXd Lx = Eigen::MatrixXd::Zero(n, ny);
  Lx.topRows(p) = k.L.topRows(p);
  const Eigen::MatrixXd LCA = Lx * k.C * k.A_a;
  const Eigen::VectorXd r_w = abs_row_sums(LCA * t.E_W.G) + abs_row_sums(Lx * k.C * floor_wa.asDiagonal());
  const Eigen::VectorXd r_v = abs_row_sums(LCA * t.E_V.G) + abs_row_sums(Lx * V.asDiagonal());
  t.Z_W = rpi(closed_loops, box_zonotope(r_w), rpi_lambda);
  t.Z_V = rpi(closed_loops, box_zonotope(r_v), rpi_lambda);
  t.j_control = 0;
  t.Z_c = t.Z_W.plus(t.Z_V);
  const Zonotope ex_box(Eigen::VectorXd::Zero(n), Eigen::MatrixXd(t.e_x_radius.asDiagonal()));
  t.x_bar = X.minus(t.Z_c.plus(ex_box));
  t.u_bar = U.minus(t.Z_c.map(K));
  // Noise margin: every half-width is h_W + s h_V.
  const Eigen::VectorXd hx_w = t.Z_W.radius() + ex_w, hx_v = t.Z_V.radius() + ex_v;
  const Eigen::VectorXd hu_w = t.Z_W.map(K).radius(), hu_v = t.Z_V.map(K).radius();
  double s = std::numeric_limits<double>::infinity();
  auto limit = [&s](const Eigen::VectorXd& half, const Eigen::VectorXd& hw, const Eigen::VectorXd& hv) {
    for (Eigen::Index i = 0; i < half.size(); ++i) {
      const double room = half(i) - hw(i);
      if (room < 0.0) {
        s = 0.0;
      } else if (hv(i) > 0.0) {
        s = std::min(s, room / hv(i));
      }
    }
  };
  limit(X.half_width(), hx_w, hx_v);
  limit(U.half_width(), hu_w, hu_v);
  t.noise_margin = s;

  // Gaussian form: the joint error (e_v, delta_v) driven by v with cov diag(V^2).
  const Eigen::MatrixXd& AK = closed_loops.front();
  Eigen::MatrixXd As = Eigen::MatrixXd::Zero(na + n, na + n);
  As.topLeftCorner(na, na) = Se;
  As.bottomLeftCorner(n, na) = LCA;
  As.bottomRightCorner(n, n) = AK;
  Eigen::MatrixXd G(na + n, ny);
  G.topRows(na) = -k.L;
  G.bottomRows(n) = Lx;
  const Eigen::MatrixXd GV = G * V.asDiagonal();
  const Eigen::MatrixXd Sigma = stationary_covariance(As, GV * GV.transpose());
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(n, na + n);
  T.leftCols(p) = Eigen::MatrixXd::Identity(n, p);
  T.rightCols(n).setIdentity();
  t.x_sigmas_v = (T * Sigma * T.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  t.e_x_sigmas_v = Eigen::VectorXd::Zero(n);
  t.e_x_sigmas_v.head(p) = Sigma.topLeftCorner(p, p).diagonal().cwiseMax(0.0).cwiseSqrt();
  t.e_x_radius_gaussian = ex_w + t.e_x_sigmas_v;
  const Eigen::MatrixXd Sd = Sigma.bottomRightCorner(n, n);
  t.delta_sigmas_v = Sd.diagonal().cwiseMax(0.0).cwiseSqrt();
  t.u_sigmas_v = (K * Sd * K.transpose()).diagonal().cwiseMax(0.0).cwiseSqrt();
  const Eigen::VectorXd hx_g = hx_w + t.x_sigmas_v, hu_g = hu_w + t.u_sigmas_v;  // each box shrinks by these
  t.x_bar_gaussian = Box(X.lo + hx_g, X.hi - hx_g);
  t.u_bar_gaussian = Box(U.lo + hu_g, U.hi - hu_g);
  s = std::numeric_limits<double>::infinity();
  limit(X.half_width(), hx_w, t.x_sigmas_v);
  limit(U.half_width(), hu_w, t.u_sigmas_v);
  t.noise_margin_gaussian = s;
  return t;
}

Eigen::MatrixXd stationary_covariance(const Eigen::MatrixXd& A, const Eigen::MatrixXd& Q) {
  if (A.rows() != A.cols() || Q.rows() != A.rows() || Q.cols() != A.rows()) {
    throw std::invalid_argument("stationary_covariance: A and Q must be square of one size");
  }
  // After j doublings Sigma sums the first 2^j terms; A^(2^j) -> 0 for a stable A.
  Eigen::MatrixXd Sigma = Q, Ak = A;
  for (int j = 0; j < 64; ++j) {
    Sigma += Ak * Sigma * Ak.transpose();
    Ak = Ak * Ak;
    if (!Ak.allFinite()) break;
    if (Ak.cwiseAbs().maxCoeff() < 1e-14) return 0.5 * (Sigma + Sigma.transpose());
  }
  throw std::runtime_error("stationary_covariance: the loop is not stable (the sum does not converge)");
}

Eigen::VectorXd innovation_sd(const KalmanDesign& k) { return diagonal_sd(k.C * k.P * k.C.transpose() + k.R); }

}  // namespace tmpc
