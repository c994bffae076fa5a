// RPI zonotopes (thesis 3.3) and their independent checks.
#include "tmpc/synthesis/rpi.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Dense>

#include "tmpc/sets/box.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

namespace {

/// Square generator matrix of W0: G_w itself when square and invertible, else the
/// half-widths of W's interval hull (the thesis' box form).
Eigen::MatrixXd square_generators(const Zonotope& W, bool& box_hull) {
  const Eigen::Index n = W.c.size();
  if (W.G.cols() == n) {
    Eigen::FullPivLU<Eigen::MatrixXd> lu(W.G);
    if (lu.isInvertible()) {
      box_hull = false;
      return W.G;
    }
  }
  box_hull = true;
  return W.radius().asDiagonal();
}

}  // namespace

RpiResult rpi_lti(const Eigen::MatrixXd& S, const Zonotope& W, const RpiSettings& s) {
  const Eigen::Index n = S.rows();
  if (W.dim() != n) throw std::invalid_argument("rpi_lti: W has dimension " + std::to_string(W.dim()) + ", S " + std::to_string(n));
  const double rho = spectral_radius(S);
  if (!(rho < 1.0)) throw std::runtime_error("rpi_lti: closed loop not stable (spectral radius " + std::to_string(rho) + ")");
  RpiResult out;
  out.method = "lti";
  const Eigen::MatrixXd Hw = square_generators(W, out.w_box_hull);
  const Eigen::MatrixXd HwInv = Hw.inverse();
  const double target = s.lambda / (s.lambda + 1.0);
  // Generators S^(j-1) H_w, ..., H_w are accumulated as S^0 H_w, S^1 H_w, ... (order is
  // irrelevant for the set).
  std::vector<Eigen::MatrixXd> powers;
  Eigen::MatrixXd SjHw = Hw;  // S^j H_w
  int j = 0;
  double alpha = 1e300;
  while (true) {
    powers.push_back(SjHw);
    SjHw = S * SjHw;
    ++j;
    // alpha(j) = max_i h_{S^j W0}(f_i) / g_i with f_i the rows of H_w^-1, g_i = 1.
    alpha = (HwInv * SjHw).cwiseAbs().rowwise().sum().maxCoeff();
    if (alpha <= target) break;
    if (j >= s.max_j) {
      throw std::runtime_error("rpi_lti: alpha(j) = " + std::to_string(alpha) + " still above " + std::to_string(target) +
                               " at j = " + std::to_string(j) + " (spectral radius " + std::to_string(rho) +
                               "); refusing to truncate");
    }
  }
  Eigen::MatrixXd G(n, static_cast<Eigen::Index>(powers.size()) * Hw.cols());
  for (std::size_t k = 0; k < powers.size(); ++k) G.middleCols(static_cast<Eigen::Index>(k) * Hw.cols(), Hw.cols()) = powers[k];
  G /= (1.0 - alpha);
  const Eigen::VectorXd center = (Eigen::MatrixXd::Identity(n, n) - S).lu().solve(W.c);
  out.Z = Zonotope(center, std::move(G));
  out.j = j;
  out.alpha = alpha;
  return out;
}

RpiResult rpi_lpv_thesis(const Eigen::MatrixXd& S0, const std::vector<Eigen::MatrixXd>& S_vertices, const Zonotope& W,
                         const RpiSettings& s) {
  Eigen::MatrixXd Sz = S0;
  for (const Eigen::MatrixXd& Si : S_vertices) Sz += Si - S0;  // (3.39): S_z = A_k + sum_i dA_k(sigma_i)
  RpiResult out = rpi_lti(Sz, W, s);
  out.method = "lpv-thesis";
  return out;
}

RpiResult rpi_lpv_robust(const Eigen::MatrixXd& S0, const std::vector<Eigen::MatrixXd>& S_vertices, const Zonotope& W,
                         const RpiSettings& s) {
  const Eigen::Index n = S0.rows();
  bool hull = false;
  const Eigen::MatrixXd Hw = square_generators(W, hull);
  auto deviation = [&](const Zonotope& Z) {
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    for (const Eigen::MatrixXd& Si : S_vertices) {
      const Zonotope dz = Z.map(Si - S0);
      d = d.cwiseMax(dz.c.cwiseAbs() + dz.radius());
    }
    return d;
  };
  auto augmented = [&](const Eigen::VectorXd& delta) {
    // W_a = W + box(delta): a parallelotope again when W is one (H_w + diag(delta) is
    // not exact for a non-diagonal H_w, so add the box as generators and take the
    // square form of the sum via its hull only when W itself is a box).
    if (!hull && Hw.isDiagonal()) return Zonotope(W.c, Eigen::MatrixXd((Hw.diagonal().cwiseAbs() + delta).asDiagonal()));
    Zonotope wa = W.plus(Zonotope(Eigen::VectorXd::Zero(n), Eigen::MatrixXd(delta.asDiagonal())));
    return Zonotope(wa.c, Eigen::MatrixXd(wa.radius().asDiagonal()));  // box hull: conservative, still valid
  };
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
  RpiResult r;
  int it = 0;
  for (; it < s.max_lpv_iterations; ++it) {
    r = rpi_lti(S0, augmented(delta), s);
    const Eigen::VectorXd next = deviation(r.Z);
    const double change = ((next - delta).array() / (next.array() + 1e-300)).abs().maxCoeff();
    delta = next;
    if (change < 1e-3) break;
  }
  // Close the fixed point: inflate, recompute, and require that the deviation of the
  // final Z fits in the inflation it was computed with.
  const Eigen::VectorXd used = delta * 1.01;
  r = rpi_lti(S0, augmented(used), s);
  const Eigen::VectorXd final_dev = deviation(r.Z);
  if (!((final_dev.array() <= used.array() + 1e-15).all())) {
    throw std::runtime_error("rpi_lpv_robust: the vertex deviation did not converge (LPV variation too large for "
                             "this gain)");
  }
  r.method = "lpv-robust";
  r.lpv_iterations = it + 1;
  r.lpv_inflation = used;
  r.w_box_hull = r.w_box_hull || hull;
  return r;
}

SupportCheck check_invariance_support(const Zonotope& Z, const std::vector<Eigen::MatrixXd>& S, const Zonotope& W,
                                      int directions, unsigned seed) {
  const Eigen::Index n = Z.c.size();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  SupportCheck out;
  const Eigen::MatrixXd GT = Z.G.transpose();
  for (int k = 0; k < directions + 2 * static_cast<int>(n); ++k) {
    Eigen::VectorXd d(n);
    if (k < 2 * n) {
      d.setZero();
      d(k / 2) = (k % 2 == 0) ? 1.0 : -1.0;
    } else {
      for (Eigen::Index i = 0; i < n; ++i) d(i) = g(rng);
      d.normalize();
    }
    const double hz = Z.support(d);
    for (std::size_t i = 0; i < S.size(); ++i) {
      // h_{S Z + W}(d) = h_Z(S'd) + h_W(d)
      const double h = Z.support(S[i].transpose() * d) + W.support(d);
      const double ratio = h / hz;
      if (ratio > out.worst_ratio) {
        out.worst_ratio = ratio;
        out.worst_vertex = static_cast<int>(i);
      }
    }
    ++out.directions;
  }
  return out;
}

SimulationCheck check_invariance_simulation(const Zonotope& Z, const std::vector<Eigen::MatrixXd>& S, const Zonotope& W,
                                            int trajectories, int steps, int directions, unsigned seed) {
  const Eigen::Index n = Z.c.size();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(S.size()) - 1);
  std::bernoulli_distribution vertex(0.5);
  // Half-space description: axes and random directions, h_Z precomputed.
  Eigen::MatrixXd D(n, 2 * n + directions);
  D.leftCols(n) = Eigen::MatrixXd::Identity(n, n);
  D.middleCols(n, n) = -Eigen::MatrixXd::Identity(n, n);
  for (int k = 0; k < directions; ++k) {
    Eigen::VectorXd d(n);
    for (Eigen::Index i = 0; i < n; ++i) d(i) = g(rng);
    D.col(2 * n + k) = d.normalized();
  }
  Eigen::VectorXd h(D.cols());
  for (Eigen::Index k = 0; k < D.cols(); ++k) h(k) = Z.support(D.col(k));
  const Eigen::MatrixXd DT = D.transpose();
  SimulationCheck out;
  out.trajectories = trajectories;
  out.steps = steps;
  Eigen::VectorXd xi(W.G.cols());
  for (int t = 0; t < trajectories; ++t) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    const bool extreme = vertex(rng);  // half the trajectories use vertices of W only
    for (int k = 0; k < steps; ++k) {
      for (Eigen::Index i = 0; i < xi.size(); ++i) xi(i) = extreme ? (u(rng) < 0 ? -1.0 : 1.0) : u(rng);
      e = S[static_cast<std::size_t>(pick(rng))] * e + W.c + W.G * xi;
      const Eigen::VectorXd ratio = (DT * e).cwiseQuotient(h);
      const double worst = ratio.maxCoeff();
      out.worst_ratio = std::max(out.worst_ratio, worst);
      if (worst > 1.0 + 1e-12) ++out.exits;
    }
  }
  return out;
}

}  // namespace tmpc
