#include "tmpc/runtime/noise_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace tmpc {

void NoiseMonitorSettings::validate() const {
  if (!(residual_below >= 0.0 && std::isfinite(residual_below))) {
    throw std::invalid_argument("noise monitor: residual_below must be >= 0, got " + std::to_string(residual_below));
  }
  if (!(filter_above >= residual_below && std::isfinite(filter_above))) {
    throw std::invalid_argument("noise monitor: filter_above (" + std::to_string(filter_above) +
                                ") must be finite and >= residual_below (" + std::to_string(residual_below) + ")");
  }
  if (!(window_s > 0.0 && window_s <= 60.0)) {
    throw std::invalid_argument("noise monitor: window must be in (0, 60] s, got " + std::to_string(window_s));
  }
}

NoiseMonitor::NoiseMonitor(const Eigen::MatrixXd& A, const std::vector<int>& rows, const Eigen::VectorXd& sigma,
                           const std::vector<StateKind>& kinds, double dt, NoiseMonitorSettings s)
    : rows_(rows), s_(s) {
  s_.validate();
  const Eigen::Index n = A.rows();
  if (A.cols() != n || static_cast<Eigen::Index>(kinds.size()) != n) {
    throw std::invalid_argument("noise monitor: A is " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()) +
                                " for " + std::to_string(kinds.size()) + " state kinds");
  }
  if (sigma.size() != static_cast<Eigen::Index>(rows.size()) || rows.empty()) {
    throw std::invalid_argument("noise monitor: " + std::to_string(sigma.size()) + " noise levels for " +
                                std::to_string(rows.size()) + " measured rows");
  }
  if (!(dt > 0.0)) throw std::invalid_argument("noise monitor: sample time must be positive");
  // R on the physical states: sigma^2 on the measured rows, 0 elsewhere.
  Eigen::VectorXd R = Eigen::VectorXd::Zero(n);
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const int r = rows[j];
    if (r < 0 || r >= n || kinds[static_cast<std::size_t>(r)] == StateKind::Integral) {
      throw std::invalid_argument("noise monitor: measured row " + std::to_string(r) + " is not a physical state");
    }
    if (!(sigma(static_cast<Eigen::Index>(j)) > 0.0)) {
      throw std::invalid_argument("noise monitor: noise level of row " + std::to_string(r) + " must be positive");
    }
    R(r) = sigma(static_cast<Eigen::Index>(j)) * sigma(static_cast<Eigen::Index>(j));
  }
  // The statistic's expectation for white noise of covariance R, per row:
  //   E[dr_i(k) (dr_i(k) - dr_i(k-1))] = (cov dr)_ii - (lag dr)_ii,
  //   cov dr = R + (I + A) R (I + A)' + A R A',  lag dr = E[dr(k) dr(k-1)'] = -(I + A) R - A R (I + A)'.
  const Eigen::MatrixXd IA = Eigen::MatrixXd::Identity(n, n) + A;
  inv_mean_.resize(static_cast<Eigen::Index>(rows.size()));
  group_rows_.assign(4, 0);
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const int r = rows[j];
    const double cov = R(r) + IA.row(r).cwiseAbs2().dot(R) + A.row(r).cwiseAbs2().dot(R);
    const double lag = -IA(r, r) * R(r) - A.row(r).cwiseProduct(IA.row(r)).dot(R);
    inv_mean_(static_cast<Eigen::Index>(j)) = 1.0 / (cov - lag);
    const int g = static_cast<int>(group_of(kinds[static_cast<std::size_t>(r)]));
    group_.push_back(g);
    ++group_rows_[static_cast<std::size_t>(g)];
  }
  window_ = std::max<long>(1, std::lround(s_.window_s / dt));
  r_prev_ = Eigen::VectorXd::Zero(n);
  d_prev_ = Eigen::VectorXd::Zero(n);
  calibrate(A, R);
}

void NoiseMonitor::reset() {
  chain_ = 0;
  samples_ = 0;
  level_ = 0.0;
  filter_ = true;
  clean_at_start_ = false;
  std::fill(std::begin(mean_), std::end(mean_), 0.0);
  std::fill(std::begin(recent_count_), std::end(recent_count_), 0);
  std::fill(std::begin(recent_next_), std::end(recent_next_), 0);
}

void NoiseMonitor::group_statistic(const Eigen::VectorXd& r, double (&stat)[4]) {
  double sum[4] = {0, 0, 0, 0};
  for (std::size_t j = 0; j < rows_.size(); ++j) {
    const int i = rows_[j];
    const double d = r(i) - r_prev_(i);
    sum[group_[j]] += d * (d - d_prev_(i)) * inv_mean_(static_cast<Eigen::Index>(j));
    d_prev_(i) = d;
  }
  for (int g = 0; g < 4; ++g) {
    const int rows = group_rows_[static_cast<std::size_t>(g)];
    stat[g] = rows > 0 ? sum[g] / rows : 0.0;
  }
}

void NoiseMonitor::store_difference(const Eigen::VectorXd& r) {
  for (const int i : rows_) d_prev_(i) = r(i) - r_prev_(i);
}

double NoiseMonitor::robust(int g, double stat) {
  // The median of the last kMedianSamples statistics (fewer at the start), no allocation.
  double* h = recent_[g];
  h[recent_next_[g]] = stat;
  recent_next_[g] = (recent_next_[g] + 1) % kMedianSamples;
  recent_count_[g] = std::min(recent_count_[g] + 1, kMedianSamples);
  double sorted[kMedianSamples];
  const int c = recent_count_[g];
  for (int i = 0; i < c; ++i) {  // insertion sort of at most kMedianSamples values
    int j = i;
    for (; j > 0 && sorted[j - 1] > h[i]; --j) sorted[j] = sorted[j - 1];
    sorted[j] = h[i];
  }
  return sorted[(c - 1) / 2] * median_scale_[g];
}

void NoiseMonitor::calibrate(const Eigen::MatrixXd& A, const Eigen::VectorXd& R) {
  // E[median of kMedianSamples] / E[statistic] per group for white noise of covariance R
  // (a fixed-seed simulation: the statistic's consecutive values are correlated through
  // the differences, which no closed form covers).
  const Eigen::Index n = A.rows();
  std::mt19937 rng(20261203u);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::VectorXd v(n), v_prev = Eigen::VectorXd::Zero(n), r(n);
  const Eigen::VectorXd sd = R.cwiseSqrt();
  double mean[4] = {0, 0, 0, 0}, med[4] = {0, 0, 0, 0};
  constexpr long kSamples = 8000;
  for (long k = 0; k < kSamples + 3; ++k) {
    for (Eigen::Index i = 0; i < n; ++i) v(i) = sd(i) * gauss(rng);
    r.noalias() = v - A * v_prev;
    v_prev = v;
    if (k == 2) store_difference(r);  // r_prev_ holds a residual of the noise
    if (k >= 3) {                       // and d_prev_ its difference
      double stat[4];
      group_statistic(r, stat);
      for (int g = 0; g < 4; ++g) {
        mean[g] += stat[g];
        med[g] += robust(g, stat[g]);
      }
    }
    r_prev_ = r;
  }
  for (int g = 0; g < 4; ++g) median_scale_[g] = med[g] > 0.0 ? mean[g] / med[g] : 1.0;
  std::fill(std::begin(recent_count_), std::end(recent_count_), 0);
  std::fill(std::begin(recent_next_), std::end(recent_next_), 0);
  r_prev_.setZero();
  d_prev_.setZero();
}

bool NoiseMonitor::update(const Eigen::VectorXd& r, bool valid) {
  clean_at_start_ = false;
  if (!valid || r.size() != r_prev_.size() || !r.allFinite()) {
    chain_ = 0;
    return filter_;
  }
  if (chain_ == 1) {
    store_difference(r);
  } else if (chain_ >= 2) {
    double stat[4];
    group_statistic(r, stat);
    ++samples_;
    const double lambda = 1.0 / static_cast<double>(std::min(samples_, window_));
    double worst = 0.0;
    for (int g = 0; g < 4; ++g) {
      if (group_rows_[static_cast<std::size_t>(g)] == 0) continue;
      mean_[g] += lambda * (robust(g, stat[g]) - mean_[g]);
      worst = std::max(worst, mean_[g]);
    }
    level_ = std::sqrt(worst);
    if (s_.enabled()) {
      const bool first = samples_ == std::min(kStartSamples, window_);
      if (filter_ && (first || samples_ >= window_) && level_ < s_.residual_below) {
        filter_ = false;
        clean_at_start_ = first;
      } else if (!filter_ && level_ > s_.filter_above) {
        filter_ = true;
      }
    }
  }
  r_prev_ = r;
  chain_ = std::min(chain_ + 1, 2);
  return filter_;
}

}  // namespace tmpc
