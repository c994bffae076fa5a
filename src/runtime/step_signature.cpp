// Step signatures and their GLR (see step_signature.hpp).
#include "tmpc/runtime/step_signature.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

namespace tmpc {

InnovationWindow::InnovationWindow(Eigen::Index rows, int window) {
  if (rows < 1 || window < 1) {
    throw std::invalid_argument("innovation window: " + std::to_string(rows) + " rows and " + std::to_string(window) +
                                " periods (both must be >= 1)");
  }
  buf_ = Eigen::MatrixXd::Zero(rows, window);
}

void InnovationWindow::push(const Eigen::VectorXd& z) {
  if (buf_.cols() == 0 || z.size() != buf_.rows()) return;  // never throws on the loop's path
  buf_.col(next_) = z;
  next_ = (next_ + 1) % window();
  if (count_ < window()) ++count_;
}

Eigen::Ref<const Eigen::VectorXd> InnovationWindow::at(int age) const {
  const int w = window();
  return buf_.col(((next_ - 1 - age) % w + w) % w);
}

namespace {

// The pseudo-inverse of a symmetric positive semidefinite M (a column no innovation of
// the window sees yet, e.g. a residual whose signature starts after one period, leaves
// M singular; its step is then the minimum-norm one).
Eigen::MatrixXd psd_pseudo_inverse(const Eigen::MatrixXd& M) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  const Eigen::VectorXd& ev = es.eigenvalues();
  const double tol = 1e-10 * std::max(1.0, ev.cwiseAbs().maxCoeff());
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(ev.size());
  for (Eigen::Index i = 0; i < ev.size(); ++i) {
    if (ev(i) > tol) inv(i) = 1.0 / ev(i);
  }
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

std::string size_of(const Eigen::MatrixXd& M) { return std::to_string(M.rows()) + "x" + std::to_string(M.cols()); }

void check_filter(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L, const Eigen::VectorXd& sd,
                  int window) {
  const Eigen::Index nx = A_a.rows(), ny = C.rows();
  if (A_a.cols() != nx || C.cols() != nx || L.rows() != nx || L.cols() != ny || sd.size() != ny) {
    throw std::invalid_argument("step signature: A_a " + size_of(A_a) + ", C " + size_of(C) + ", L " + size_of(L) +
                                ", sd " + std::to_string(sd.size()) +
                                " do not fit (A_a nx x nx, C ny x nx, L nx x ny, sd ny)");
  }
  if (!(sd.array() > 0.0).all() || !sd.allFinite()) throw std::invalid_argument("step signature: an innovation deviation is not > 0");
  if (window < 1) throw std::invalid_argument("step signature: window " + std::to_string(window) + " (must be >= 1)");
}

}  // namespace

StepSignature::StepSignature(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L,
                             const Eigen::VectorXd& sd, const std::vector<Eigen::Index>& columns, int window)
    : columns_(columns) {
  check_filter(A_a, C, L, sd, window);
  if (columns.empty()) throw std::invalid_argument("step signature: no column");
  const Eigen::Index nx = A_a.rows();
  const auto nh = static_cast<Eigen::Index>(columns.size());
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(nx, nh);
  for (Eigen::Index j = 0; j < nh; ++j) {
    const Eigen::Index c = columns[static_cast<std::size_t>(j)];
    if (c < 0 || c >= nx) {
      throw std::invalid_argument("step signature: column " + std::to_string(c) + " outside the " + std::to_string(nx) +
                                  " augmented states");
    }
    if (C.col(c).cwiseAbs().maxCoeff() > 0.0) {
      throw std::invalid_argument("step signature: column " + std::to_string(c) + " is measured (C's column not zero)");
    }
    E(c, j) = 1.0;
  }
  build(A_a, C, L, sd, E, window, Eigen::VectorXd(), 0.0);
}

StepSignature StepSignature::along(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L,
                                   const Eigen::VectorXd& sd, const Eigen::MatrixXd& E, int window,
                                   const Eigen::VectorXd& prior_sd, double determined) {
  check_filter(A_a, C, L, sd, window);
  if (E.rows() != A_a.rows() || E.cols() < 1 || !E.allFinite()) {
    throw std::invalid_argument("step signature: E " + size_of(E) + " (must be " + std::to_string(A_a.rows()) +
                                " x h, h >= 1, finite)");
  }
  for (Eigen::Index j = 0; j < E.cols(); ++j) {
    const double ce = (C * E.col(j)).cwiseAbs().maxCoeff();
    if (ce > 1e-12 * std::max(1.0, E.col(j).cwiseAbs().maxCoeff())) {
      throw std::invalid_argument("step signature: direction " + std::to_string(j) + " is measured (C E's column " +
                                  std::to_string(ce) + ", not 0)");
    }
  }
  if (prior_sd.size() != 0 && (prior_sd.size() != E.cols() || !(prior_sd.array() > 0.0).all() || !prior_sd.allFinite())) {
    throw std::invalid_argument("step signature: the prior's deviations (" + std::to_string(prior_sd.size()) +
                                ") must be one per direction (" + std::to_string(E.cols()) + "), finite and > 0");
  }
  if (prior_sd.size() != 0 && !(determined > 0.0 && determined < 1.0)) {
    throw std::invalid_argument("step signature: the determined fraction " + std::to_string(determined) +
                                " (must be in (0, 1))");
  }
  StepSignature sig;
  sig.build(A_a, C, L, sd, E, window, prior_sd, determined);
  return sig;
}

void StepSignature::build(const Eigen::MatrixXd& A_a, const Eigen::MatrixXd& C, const Eigen::MatrixXd& L,
                          const Eigen::VectorXd& sd, const Eigen::MatrixXd& E, int window, const Eigen::VectorXd& prior_sd,
                          double determined) {
  const Eigen::Index nx = A_a.rows(), nh = E.cols();
  const Eigen::MatrixXd Phi = A_a * (Eigen::MatrixXd::Identity(nx, nx) - L * C);  // the prediction error's map
  const Eigen::VectorXd w = sd.cwiseInverse();
  Eigen::MatrixXd PhiE = E, M = Eigen::MatrixXd::Zero(nh, nh);
  const Eigen::MatrixXd S = prior_sd.size() == 0 ? Eigen::MatrixXd() : Eigen::MatrixXd(prior_sd.asDiagonal());
  for (int k = 1; k <= window; ++k) {
    PhiE = Phi * PhiE;
    J_.push_back(PhiE);
    G_.push_back(w.asDiagonal() * (C * PhiE));
    M += G_.back().transpose() * G_.back();
    Minv_.push_back(psd_pseudo_inverse(M));
    if (prior_sd.size() == 0) {
      Mread_.push_back(Minv_.back());
    } else {
      // Whitened by the prior, S M S has the prior's variance over the estimate's along
      // its eigenvectors: read those at least 1 / determined^2, the rest left at zero.
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S * M * S);
      Eigen::VectorXd inv = Eigen::VectorXd::Zero(nh);
      for (Eigen::Index i = 0; i < nh; ++i) {
        if (es.eigenvalues()(i) * determined * determined >= 1.0) inv(i) = 1.0 / es.eigenvalues()(i);
      }
      Mread_.push_back(S * es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose() * S);
    }
  }
  b_ = Eigen::VectorXd::Zero(nh);
  t_ = Eigen::VectorXd::Zero(nh);
}

StepSignature::Fit StepSignature::fit(const InnovationWindow& z, Eigen::VectorXd* step) const {
  Fit best;
  const int n = std::min(z.size(), static_cast<int>(G_.size()));
  for (int m = 1; m <= n; ++m) {
    // Onset m periods ago: the innovation of age m - k carries G(k).
    b_.setZero();
    for (int k = 1; k <= m; ++k) b_.noalias() += G_[static_cast<std::size_t>(k - 1)].transpose() * z.at(m - k);
    t_.noalias() = Minv_[static_cast<std::size_t>(m - 1)] * b_;
    const double l = b_.dot(t_);
    if (l > best.statistic) {
      best.statistic = l;
      best.onset = m;
      if (step != nullptr && step->size() == t_.size()) *step = t_;
    }
  }
  return best;
}

void StepSignature::read_step(const InnovationWindow& z, int m, Eigen::VectorXd& step) const {
  if (step.size() != b_.size()) return;  // never throws on the loop's path
  m = std::min({m, z.size(), static_cast<int>(G_.size())});
  if (m < 1) {
    step.setZero();
    return;
  }
  b_.setZero();
  for (int k = 1; k <= m; ++k) b_.noalias() += G_[static_cast<std::size_t>(k - 1)].transpose() * z.at(m - k);
  step.noalias() = Mread_[static_cast<std::size_t>(m - 1)] * b_;
}

double chi_square_quantile(int dof, double p) {
  if (dof < 1 || !(p > 0.0 && p < 1.0)) {
    throw std::invalid_argument("chi-square quantile: dof " + std::to_string(dof) + ", p " + std::to_string(p) +
                                " (need dof >= 1 and 0 < p < 1)");
  }
  // The standard normal quantile by bisection of its CDF, 0.5 erfc(-x / sqrt 2).
  double lo = -10.0, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
  }
  const double x = 0.5 * (lo + hi), a = 2.0 / (9.0 * dof);
  return dof * std::pow(std::max(0.0, 1.0 - a + x * std::sqrt(a)), 3);
}

}  // namespace tmpc
