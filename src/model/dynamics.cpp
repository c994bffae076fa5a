// Euler-Lagrange dynamics of the tiltrotor from its kinematic tree (thesis 5.1).
#include "tmpc/model/dynamics.hpp"

#include <Eigen/Cholesky>

#include <array>

#include "tmpc/model/dual.hpp"

namespace tmpc {

namespace {

template <class T, int R, int C>
Eigen::Matrix<T, R, C> value_part(const Eigen::Matrix<Dual<T>, R, C>& m) {
  return m.unaryExpr([](const Dual<T>& a) { return a.v; });
}
template <class T, int R, int C>
Eigen::Matrix<T, R, C> deriv_part(const Eigen::Matrix<Dual<T>, R, C>& m) {
  return m.unaryExpr([](const Dual<T>& a) { return a.d; });
}

/// Solve A x = b for symmetric positive definite A (Cholesky), any scalar type.
template <class T, int N>
Eigen::Matrix<T, N, 1> spd_solve(const Eigen::Matrix<T, N, N>& a, const Eigen::Matrix<T, N, 1>& b) {
  using std::sqrt;
  Eigen::Matrix<T, N, N> l = Eigen::Matrix<T, N, N>::Zero();
  for (int j = 0; j < N; ++j) {
    T s = a(j, j);
    for (int k = 0; k < j; ++k) s -= l(j, k) * l(j, k);
    l(j, j) = sqrt(s);
    for (int i = j + 1; i < N; ++i) {
      T t = a(i, j);
      for (int k = 0; k < j; ++k) t -= l(i, k) * l(j, k);
      l(i, j) = t / l(j, j);
    }
  }
  Eigen::Matrix<T, N, 1> y;
  for (int i = 0; i < N; ++i) {
    T t = b(i);
    for (int k = 0; k < i; ++k) t -= l(i, k) * y(k);
    y(i) = t / l(i, i);
  }
  Eigen::Matrix<T, N, 1> x;
  for (int i = N - 1; i >= 0; --i) {
    T t = y(i);
    for (int k = i + 1; k < N; ++k) t -= l(k, i) * x(k);
    x(i) = t / l(i, i);
  }
  return x;
}

}  // namespace

TiltrotorModel::TiltrotorModel(const VehicleParams& params) : params_(params), tree_(params) {}

template <class T>
DynamicsTerms<T> TiltrotorModel::terms(const T* q, const T* qd) const {
  using DT = Dual<T>;
  // One pass with q + eps q': values give the Jacobians, derivatives J-dot.
  std::array<DT, kNq> qq;
  for (int i = 0; i < kNq; ++i) qq[static_cast<std::size_t>(i)] = DT(q[i], qd[i]);
  const TreePose<DT> pose = tree_.pose(qq.data());
  const Eigen::Map<const Eigen::Matrix<T, kNq, 1>> v(qd);

  DynamicsTerms<T> out;
  out.M.setZero();
  out.c.setZero();
  out.G.setZero();
  out.L_in.setZero();
  const T g(params_.gravity);
  Jac<DT> jv, jw;
  for (const TreeBody& b : tree_.bodies()) {
    const auto f = static_cast<std::size_t>(b.frame);
    const Vec3<DT> com = pose.p[f] + pose.R[f] * b.com.cast<DT>();
    tree_.jacobian(pose, b.frame, com, jv, jw);
    const Jac<T> Jv = value_part(jv), Jvd = deriv_part(jv);
    const Jac<T> Jw = value_part(jw), Jwd = deriv_part(jw);
    const Mat3<T> R = value_part(pose.R[f]);
    const Mat3<T> Iw = R * b.inertia.cast<T>() * R.transpose();
    const T m(b.mass);
    out.M += m * (Jv.transpose() * Jv) + Jw.transpose() * Iw * Jw;
    const Vec3<T> w = Jw * v;
    const Vec3<T> a0 = Jvd * v;  // CoM acceleration with q'' = 0
    const Vec3<T> wd0 = Jwd * v;  // angular acceleration with q'' = 0
    const Vec3<T> Iww = Iw * w;
    out.c += m * (Jv.transpose() * a0) + Jw.transpose() * (Iw * wd0 + w.cross(Iww));
    out.G += (g * m) * Jv.row(2).transpose();
  }
  // Thrust along +z of each rotor frame at its pivot, rotor drag torque about it,
  // servo torque on its tilt coordinate (model spec section 4).
  const std::array<int, 2> rotor_frames = {KinematicTree::kRotorRightFrame, KinematicTree::kRotorLeftFrame};
  const std::array<double, 2> spins = {params_.spin_right, params_.spin_left};
  const std::array<int, 2> tilts = {kAlphaR, kAlphaL};
  for (std::size_t i = 0; i < 2; ++i) {
    const auto f = static_cast<std::size_t>(rotor_frames[i]);
    tree_.jacobian(pose, rotor_frames[i], pose.p[f], jv, jw);
    const Jac<T> Jv = value_part(jv), Jw = value_part(jw);
    const Vec3<T> n = value_part(pose.R[f]).col(2);
    const T k(spins[i] * params_.drag_torque_ratio);
    out.L_in.col(static_cast<int>(i)) = Jv.transpose() * n + k * (Jw.transpose() * n);
    out.L_in(tilts[i], 2 + static_cast<int>(i)) = T(1.0);
  }
  return out;
}

template <class T>
Eigen::Matrix<T, kNq, kNq> TiltrotorModel::mass_matrix_t(const T* q) const {
  const TreePose<T> pose = tree_.pose(q);
  Eigen::Matrix<T, kNq, kNq> M = Eigen::Matrix<T, kNq, kNq>::Zero();
  Jac<T> jv, jw;
  for (const TreeBody& b : tree_.bodies()) {
    const auto f = static_cast<std::size_t>(b.frame);
    const Vec3<T> com = pose.p[f] + pose.R[f] * b.com.cast<T>();
    tree_.jacobian(pose, b.frame, com, jv, jw);
    const Mat3<T> Iw = pose.R[f] * b.inertia.cast<T>() * pose.R[f].transpose();
    M += T(b.mass) * (jv.transpose() * jv) + jw.transpose() * Iw * jw;
  }
  return M;
}

template <class T>
Eigen::Matrix<T, kNx, 1> TiltrotorModel::state_derivative_t(const T* x, const T* u, const T* d) const {
  const T* q = x;
  const T* qd = x + kNq;
  const DynamicsTerms<T> t = terms(q, qd);
  Eigen::Matrix<T, kNq, 1> rhs = -t.c - t.G;
  for (int j = 0; j < kNu; ++j) rhs += t.L_in.col(j) * u[j];
  for (int i = 0; i < kNq; ++i) rhs(i) -= T(params_.friction[static_cast<std::size_t>(i)]) * qd[i];
  for (int i = 0; i < kNd; ++i) rhs(i) += d[i];  // L_ab = [I3; 0]
  const Eigen::Matrix<T, kNq, 1> qdd = spd_solve<T, kNq>(t.M, rhs);
  Eigen::Matrix<T, kNx, 1> xd;
  for (int i = 0; i < kNq; ++i) {
    xd(i) = qd[i];
    xd(kNq + i) = qdd(i);
  }
  return xd;
}

Mat10 TiltrotorModel::mass_matrix(const Vec10& q) const { return mass_matrix_t<double>(q.data()); }

Vec10 TiltrotorModel::body_force(const Vec10& q, const Eigen::Vector3d& F) const {
  const TreePose<double> pose = tree_.pose(q.data());
  const TreeBody& b = tree_.bodies()[KinematicTree::kBody];
  const auto f = static_cast<std::size_t>(b.frame);
  const Vec3<double> com = pose.p[f] + pose.R[f] * b.com;
  Jac<double> jv, jw;
  tree_.jacobian(pose, b.frame, com, jv, jw);
  return jv.transpose() * F;
}

State20 TiltrotorModel::state_derivative(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d_load,
                                         const Eigen::Vector3d& f_body) const {
  if (f_body.isZero(0.0)) return state_derivative(x, u, d_load);
  // M q'' = ... + L_ab d + Jv_body' F: solved with the body force moved into q''.
  const Vec10 q = x.head<kNq>();
  const Vec10 extra = mass_matrix(q).llt().solve(body_force(q, f_body));
  State20 xd = state_derivative(x, u, d_load);
  xd.tail<kNq>() += extra;
  return xd;
}

State20 rk4_step(const TiltrotorModel& model, const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d_load,
                 const Eigen::Vector3d& f_body, double h) {
  const State20 k1 = model.state_derivative(x, u, d_load, f_body);
  const State20 k2 = model.state_derivative(x + 0.5 * h * k1, u, d_load, f_body);
  const State20 k3 = model.state_derivative(x + 0.5 * h * k2, u, d_load, f_body);
  const State20 k4 = model.state_derivative(x + h * k3, u, d_load, f_body);
  return x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

Vec10 TiltrotorModel::gravity_vector(const Vec10& q) const {
  const Vec10 zero = Vec10::Zero();
  return terms<double>(q.data(), zero.data()).G;
}

InputMat TiltrotorModel::input_matrix(const Vec10& q) const {
  const Vec10 zero = Vec10::Zero();
  return terms<double>(q.data(), zero.data()).L_in;
}

Vec10 TiltrotorModel::coriolis_vector(const Vec10& q, const Vec10& qd) const {
  return terms<double>(q.data(), qd.data()).c;
}

Mat10 TiltrotorModel::coriolis_matrix(const Vec10& q, const Vec10& qd) const {
  // dM/dq_i by a dual number seeded on q_i.
  std::array<Mat10, kNq> dM;
  for (int i = 0; i < kNq; ++i) {
    std::array<D1, kNq> qq;
    for (int j = 0; j < kNq; ++j) qq[static_cast<std::size_t>(j)] = D1(q(j), i == j ? 1.0 : 0.0);
    dM[static_cast<std::size_t>(i)] = deriv_part(mass_matrix_t<D1>(qq.data()));
  }
  // C_kj = sum_i 0.5 (dM_kj/dq_i + dM_ki/dq_j - dM_ij/dq_k) q'_i
  Mat10 C = Mat10::Zero();
  for (int k = 0; k < kNq; ++k) {
    for (int j = 0; j < kNq; ++j) {
      double s = 0.0;
      for (int i = 0; i < kNq; ++i) {
        s += 0.5 * (dM[static_cast<std::size_t>(i)](k, j) + dM[static_cast<std::size_t>(j)](k, i) -
                    dM[static_cast<std::size_t>(k)](i, j)) * qd(i);
      }
      C(k, j) = s;
    }
  }
  return C;
}

Mat10 TiltrotorModel::friction_matrix() const {
  Mat10 L = Mat10::Zero();
  for (int i = 0; i < kNq; ++i) L(i, i) = params_.friction[static_cast<std::size_t>(i)];
  return L;
}

Eigen::Matrix<double, kNq, kNd> TiltrotorModel::disturbance_matrix() const {
  Eigen::Matrix<double, kNq, kNd> L = Eigen::Matrix<double, kNq, kNd>::Zero();
  L.topRows<3>().setIdentity();
  return L;
}

Vec10 TiltrotorModel::acceleration(const Vec10& q, const Vec10& qd, const Eigen::Vector4d& u,
                                   const Eigen::Vector3d& d) const {
  State20 x;
  x << q, qd;
  return state_derivative(x, u, d).tail<kNq>();
}

State20 TiltrotorModel::state_derivative(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d) const {
  return state_derivative_t<double>(x.data(), u.data(), d.data());
}

Linearization TiltrotorModel::linearize(const State20& x, const Eigen::Vector4d& u, const Eigen::Vector3d& d) const {
  Linearization lin;
  constexpr int kN = kNx + kNu + kNd;
  std::array<D1, kN> z;
  for (int i = 0; i < kNx; ++i) z[static_cast<std::size_t>(i)] = D1(x(i), 0.0);
  for (int i = 0; i < kNu; ++i) z[static_cast<std::size_t>(kNx + i)] = D1(u(i), 0.0);
  for (int i = 0; i < kNd; ++i) z[static_cast<std::size_t>(kNx + kNu + i)] = D1(d(i), 0.0);
  for (int j = 0; j < kN; ++j) {
    z[static_cast<std::size_t>(j)].d = 1.0;
    const auto f = state_derivative_t<D1>(z.data(), z.data() + kNx, z.data() + kNx + kNu);
    const Eigen::Matrix<double, kNx, 1> col = deriv_part(f);
    if (j < kNx) {
      lin.A.col(j) = col;
    } else if (j < kNx + kNu) {
      lin.B.col(j - kNx) = col;
    } else {
      lin.D.col(j - kNx - kNu) = col;
    }
    z[static_cast<std::size_t>(j)].d = 0.0;
  }
  return lin;
}

double TiltrotorModel::kinetic_energy(const Vec10& q, const Vec10& qd) const {
  return 0.5 * qd.dot(mass_matrix(q) * qd);
}

double TiltrotorModel::potential_energy(const Vec10& q) const {
  const TreePose<double> pose = tree_.pose(q.data());
  double u = 0.0;
  for (const TreeBody& b : tree_.bodies()) {
    const auto f = static_cast<std::size_t>(b.frame);
    u += b.mass * params_.gravity * (pose.p[f] + pose.R[f] * b.com).z();
  }
  return u;
}

template DynamicsTerms<double> TiltrotorModel::terms<double>(const double*, const double*) const;
template DynamicsTerms<D1> TiltrotorModel::terms<D1>(const D1*, const D1*) const;
template Eigen::Matrix<double, kNq, kNq> TiltrotorModel::mass_matrix_t<double>(const double*) const;
template Eigen::Matrix<D1, kNq, kNq> TiltrotorModel::mass_matrix_t<D1>(const D1*) const;
template Eigen::Matrix<double, kNx, 1> TiltrotorModel::state_derivative_t<double>(const double*, const double*,
                                                                                 const double*) const;
template Eigen::Matrix<D1, kNx, 1> TiltrotorModel::state_derivative_t<D1>(const D1*, const D1*, const D1*) const;

}  // namespace tmpc
