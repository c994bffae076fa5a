// Hover equilibrium by Gauss-Newton on L_in(q) u - G(q) = 0.
#include "tmpc/model/equilibrium.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include <Eigen/Dense>

#include "tmpc/model/dual.hpp"

namespace tmpc {

namespace {

/// Residual L_in(q) u - G(q) at zero velocity; z = (angles, u).
template <class T>
Eigen::Matrix<T, kNq, 1> residual(const TiltrotorModel& model, double yaw, const T* z) {
  std::array<T, kNq> q{};
  std::array<T, kNq> qd{};
  for (auto& v : q) v = T(0.0);
  for (auto& v : qd) v = T(0.0);
  q[kPsi] = T(yaw);
  for (int i = 0; i < 4; ++i) q[static_cast<std::size_t>(kGamma1 + i)] = z[i];
  const DynamicsTerms<T> t = model.terms<T>(q.data(), qd.data());
  Eigen::Matrix<T, kNq, 1> r = -t.G;
  for (int j = 0; j < kNu; ++j) r += t.L_in.col(j) * z[4 + j];
  return r;
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
  for (int it = 0; it < 50; ++it) {
    std::array<D1, 8> zz;
    Eigen::Matrix<double, kNq, 8> J;
    Eigen::Matrix<double, kNq, 1> r;
    for (int j = 0; j < 8; ++j) {
      for (int i = 0; i < 8; ++i) zz[static_cast<std::size_t>(i)] = D1(z(i), i == j ? 1.0 : 0.0);
      const auto rr = residual<D1>(model, yaw, zz.data());
      for (int i = 0; i < kNq; ++i) {
        J(i, j) = rr(i).d;
        r(i) = rr(i).v;
      }
    }
    eq.iterations = it;
    eq.residual = r.cwiseAbs().maxCoeff();
    if (eq.residual < tolerance) break;
    z -= J.colPivHouseholderQr().solve(r);
  }
  eq.angles = z.head<4>();
  eq.u = z.tail<4>();
  const auto r = residual<double>(model, yaw, z.data());
  eq.residual = r.cwiseAbs().maxCoeff();
  if (!(eq.residual < tolerance)) {
    throw std::runtime_error("hover equilibrium: Gauss-Newton stopped at residual " + std::to_string(eq.residual) +
                             " (tolerance " + std::to_string(tolerance) + ")");
  }
  return eq;
}

}  // namespace tmpc
