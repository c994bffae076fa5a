// Hover equilibrium and trim by Gauss-Newton with exact Jacobians.
#include "tmpc/model/equilibrium.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "tmpc/model/dual.hpp"

namespace tmpc {

namespace {

/// Residual L_in(q) u - (M q'' + C q' + L_fr q' + G) with q'' = (sigma, 0), q' = (v, 0).
/// z holds the free coordinates listed in `free` (indices into q), then u. With
/// `L_in` given, L_in(q) is written there (the residual's Jacobian in u: it is linear in u).
template <class T, int NF>
Eigen::Matrix<T, kNq, 1> residual(const TiltrotorModel& model, double yaw, const Eigen::Vector3d& sigma,
                                  const Eigen::Vector3d& v, const std::array<int, NF>& free, const T* z,
                                  Eigen::Matrix<T, kNq, kNu>* L_in = nullptr) {
  std::array<T, kNq> q{}, qd{};
  for (auto& a : q) a = T(0.0);
  for (auto& a : qd) a = T(0.0);
  q[kPsi] = T(yaw);
  for (int i = 0; i < 3; ++i) qd[static_cast<std::size_t>(i)] = T(v(i));
  for (int i = 0; i < NF; ++i) q[static_cast<std::size_t>(free[static_cast<std::size_t>(i)])] = z[i];
  const DynamicsTerms<T> t = model.terms<T>(q.data(), qd.data());
  Eigen::Matrix<T, kNq, 1> r = -t.G - t.c;
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < kNq; ++k) r(k) -= t.M(k, i) * T(sigma(i));
  }
  const auto& mu = model.params().friction;
  for (int i = 0; i < 3; ++i) r(i) -= T(mu[static_cast<std::size_t>(i)] * v(i));
  for (int j = 0; j < kNu; ++j) r += t.L_in.col(j) * z[NF + j];
  if (L_in != nullptr) *L_in = t.L_in;
  return r;
}

/// Gauss-Newton on residual() over NF free coordinates and the 4 inputs.
template <int NF>
Eigen::Matrix<double, NF + 4, 1> gauss_newton(const TiltrotorModel& model, double yaw, const Eigen::Vector3d& sigma,
                                             const Eigen::Vector3d& v, const std::array<int, NF>& free,
                                             Eigen::Matrix<double, NF + 4, 1> z, double tolerance, double& res,
                                             int& iterations, const char* what) {
  constexpr int n = NF + 4;
  for (iterations = 0; iterations < 50; ++iterations) {
    Eigen::Matrix<double, kNq, n> J;
    Eigen::Matrix<double, kNq, kNu> L_in;
    // The residual and its u-columns (L_in: linear in u) from one plain evaluation; a
    // dual pass per free coordinate for the rest.
    const Eigen::Matrix<double, kNq, 1> r = residual<double, NF>(model, yaw, sigma, v, free, z.data(), &L_in);
    J.template rightCols<kNu>() = L_in;
    std::array<D1, n> zz;
    for (int j = 0; j < NF; ++j) {
      for (int i = 0; i < n; ++i) zz[static_cast<std::size_t>(i)] = D1(z(i), i == j ? 1.0 : 0.0);
      const auto rr = residual<D1, NF>(model, yaw, sigma, v, free, zz.data());
      for (int i = 0; i < kNq; ++i) J(i, j) = rr(i).d;
    }
    res = r.cwiseAbs().maxCoeff();
    if (res < tolerance) break;
    z -= J.colPivHouseholderQr().solve(r);
  }
  res = residual<double, NF>(model, yaw, sigma, v, free, z.data()).cwiseAbs().maxCoeff();
  if (!(res < tolerance) && what != nullptr) {
    throw std::runtime_error(std::string(what) + ": Gauss-Newton stopped at residual " + std::to_string(res) +
                             " (tolerance " + std::to_string(tolerance) + ")");
  }
  return z;
}

}  // namespace

Vec10 Equilibrium::q() const {
  Vec10 q = Vec10::Zero();
  q.segment<4>(kGamma1) = angles;
  return q;
}

Equilibrium solve_hover_equilibrium(const TiltrotorModel& model, double yaw, double tolerance) {
  const VehicleParams& p = model.params();
  const double weight = p.gravity * (p.load_mass + p.body_mass + 2.0 * p.rotor_mass);
  Eigen::Matrix<double, 8, 1> z;
  z << 0, 0, 0, 0, 0.5 * weight, 0.5 * weight, 0, 0;
  Equilibrium eq;
  const std::array<int, 4> free = {kGamma1, kGamma2, kAlphaR, kAlphaL};
  z = gauss_newton<4>(model, yaw, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), free, z, tolerance, eq.residual,
                      eq.iterations, "hover equilibrium");
  eq.angles = z.head<4>();
  eq.u = z.tail<4>();
  return eq;
}

Trim trim_start(const Equilibrium& e) {
  Trim t;
  t.angles = e.angles;
  t.u = e.u;
  return t;
}

Trim solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                double yaw, const Equilibrium& start, double tolerance) {
  return solve_trim(model, sigma, velocity, yaw, trim_start(start), tolerance);
}

bool try_solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                    double yaw, const Trim& start, Trim& out, double tolerance) {
  Eigen::Matrix<double, 10, 1> z;
  z << start.attitude, start.angles, start.u;
  const std::array<int, 6> free = {kPhi, kTheta, kGamma1, kGamma2, kAlphaR, kAlphaL};
  double res = 0.0;
  int it = 0;
  z = gauss_newton<6>(model, yaw, sigma, velocity, free, z, tolerance, res, it, nullptr);
  if (!(res < tolerance)) return false;
  out.attitude = z.head<2>();
  out.angles = z.segment<4>(2);
  out.u = z.tail<4>();
  out.residual = res;
  out.iterations = it;
  return true;
}

Trim solve_trim(const TiltrotorModel& model, const Eigen::Vector3d& sigma, const Eigen::Vector3d& velocity,
                double yaw, const Trim& start, double tolerance) {
  Eigen::Matrix<double, 10, 1> z;
  z << start.attitude, start.angles, start.u;
  const std::array<int, 6> free = {kPhi, kTheta, kGamma1, kGamma2, kAlphaR, kAlphaL};
  Trim t;
  z = gauss_newton<6>(model, yaw, sigma, velocity, free, z, tolerance, t.residual, t.iterations, "trim");
  t.attitude = z.head<2>();
  t.angles = z.segment<4>(2);
  t.u = z.tail<4>();
  return t;
}

}  // namespace tmpc
