// Linear error model along the helix: LPV form, integrals, discretization,
// normalization (thesis 5.2).
#include "tmpc/model/error_model.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "tmpc/model/reference.hpp"

namespace tmpc {

Mat20 LpvModel::at(const Eigen::Vector3d& sigma) const {
  Mat20 A = A0;
  for (int i = 0; i < 3; ++i) A += sigma(i) * A_sigma[static_cast<std::size_t>(i)];
  return A;
}

void augment_with_integrals(const Mat20& A, const Eigen::Matrix<double, kNx, kNu>& B,
                            const Eigen::Matrix<double, kNx, kNd>& D, Mat24& Aa, Mat24x4& Ba, Mat24x3& Da) {
  Aa.setZero();
  Ba.setZero();
  Da.setZero();
  Aa.topLeftCorner<kNx, kNx>() = A;
  // Integral rows: d/dt int(e) = e for x, y, z and psi (C of (5.5)).
  const int integrated[4] = {kX, kY, kZ, kPsi};
  for (int i = 0; i < 4; ++i) Aa(kNx + i, integrated[i]) = 1.0;
  Ba.topRows<kNx>() = B;
  Da.topRows<kNx>() = D;
}

void discretize(const Mat24& Ac, const Mat24x4& Bc, const Mat24x3& Dc, double T, Discretization method, Mat24& A,
                Mat24x4& B, Mat24x3& D) {
  if (method == Discretization::Euler) {
    // Thesis (5.8) with the sign of E1 corrected: A_z = I + A_a T.
    A = Mat24::Identity() + Ac * T;
    B = Bc * T;
    D = Dc * T;
    return;
  }
  // Exact zero-order hold: expm([A B D; 0 0 0] T) = [A_z B_z D_z; 0 I 0; 0 0 I].
  constexpr int n = kNa + kNu + kNd;
  Eigen::Matrix<double, n, n> blk = Eigen::Matrix<double, n, n>::Zero();
  blk.topLeftCorner<kNa, kNa>() = Ac * T;
  blk.block<kNa, kNu>(0, kNa) = Bc * T;
  blk.block<kNa, kNd>(0, kNa + kNu) = Dc * T;
  const Eigen::Matrix<double, n, n> e = blk.exp();
  A = e.topLeftCorner<kNa, kNa>();
  B = e.block<kNa, kNu>(0, kNa);
  D = e.block<kNa, kNd>(0, kNa + kNu);
}

namespace {

State20 stack(const Vec10& q, const Vec10& qd) {
  State20 x;
  x << q, qd;
  return x;
}

}  // namespace

ErrorModel build_error_model(const Config& cfg, const TiltrotorModel& model) {
  ErrorModel em;
  em.sample_time = cfg.sample_time;
  em.discretization = cfg.error_model.discretization;
  em.equilibrium = solve_hover_equilibrium(model, cfg.reference.yaw);
  const HelixTrajectory traj(cfg.reference, em.equilibrium.angles);
  const Eigen::Vector3d no_d = Eigen::Vector3d::Zero();

  // A(sigma) at the reference attitude with zero velocity: f is affine in u and
  // u_r(sigma) is affine in sigma, so A(sigma) is exactly affine.
  ReferencePoint hover = traj.at(0.0);
  hover.q.head<3>().setZero();
  hover.qd.setZero();
  hover.qdd.setZero();
  auto linear_at = [&](const Eigen::Vector3d& sigma) {
    ReferencePoint r = hover;
    r.qdd.head<3>() = sigma;
    return model.linearize(stack(r.q, r.qd), feedforward(model, r), no_d);
  };
  const Linearization l0 = linear_at(Eigen::Vector3d::Zero());
  LpvModel& lpv = em.lpv;
  lpv.A0 = l0.A;
  lpv.B = l0.B;
  lpv.D = l0.D;
  lpv.A_sigma.resize(3);
  for (int i = 0; i < 3; ++i) {
    lpv.A_sigma[static_cast<std::size_t>(i)] = linear_at(Eigen::Vector3d::Unit(i)).A - l0.A;
  }

  // Sample the mission: sigma's box, u_r's range, and how affine the true A(t) is.
  lpv.sigma_min.setConstant(1e300);
  lpv.sigma_max.setConstant(-1e300);
  em.u_r_min.setConstant(1e300);
  em.u_r_max.setConstant(-1e300);
  const double a0 = lpv.A0.norm();
  double worst_abs = 0.0;
  double worst_var = 0.0;
  double worst_sigma = 0.0;
  const double step = cfg.error_model.lpv_sample_step;
  const int samples = std::max(1, static_cast<int>(std::floor(cfg.simulation.duration / step + 1e-9))) + 1;
  for (int k = 0; k < samples; ++k) {
    const double t = std::min(k * step, cfg.simulation.duration);
    const ReferencePoint r = traj.at(t);
    const Eigen::Vector4d ur = feedforward(model, r);
    em.u_r_min = em.u_r_min.cwiseMin(ur);
    em.u_r_max = em.u_r_max.cwiseMax(ur);
    const Eigen::Vector3d s = r.sigma();
    lpv.sigma_min = lpv.sigma_min.cwiseMin(s);
    lpv.sigma_max = lpv.sigma_max.cwiseMax(s);
    const Mat20 A_true = model.linearize(stack(r.q, r.qd), ur, no_d).A;
    const Mat20 A_lpv = lpv.at(s);
    worst_abs = std::max(worst_abs, (A_true - A_lpv).norm());
    worst_var = std::max(worst_var, (A_true - lpv.A0).norm());
    worst_sigma = std::max(worst_sigma, (A_lpv - lpv.A0).norm());
  }
  lpv.affinity_residual = worst_abs / a0;
  lpv.affinity_residual_relative = worst_var > 0.0 ? worst_abs / worst_var : 0.0;
  lpv.sigma_part = worst_sigma / a0;
  for (int v = 0; v < 8; ++v) {
    Eigen::Vector3d s;
    for (int i = 0; i < 3; ++i) s(i) = ((v >> i) & 1) ? lpv.sigma_max(i) : lpv.sigma_min(i);
    lpv.vertex_sigma.push_back(s);
  }

  // Augment and discretize the nominal model and every vertex.
  augment_with_integrals(lpv.A0, lpv.B, lpv.D, em.A_c, em.B_c, em.D_c);
  discretize(em.A_c, em.B_c, em.D_c, em.sample_time, em.discretization, em.A, em.B, em.D);
  for (const Eigen::Vector3d& s : lpv.vertex_sigma) {
    Mat24 Ac, Ad;
    Mat24x4 Bc, Bd;
    Mat24x3 Dc, Dd;
    augment_with_integrals(lpv.at(s), lpv.B, lpv.D, Ac, Bc, Dc);
    discretize(Ac, Bc, Dc, em.sample_time, em.discretization, Ad, Bd, Dd);
    em.A_vertices.push_back(Ad);
  }

  // Input box in error coordinates: must hold for every u_r along the mission.
  em.input_error_min = cfg.input_min - em.u_r_min;
  em.input_error_max = cfg.input_max - em.u_r_max;

  // Normalization (5.10)-(5.11): the state error box and the input range become unit boxes.
  em.N_x = cfg.state_error_max.cwiseInverse();
  em.N_u = 2.0 * (cfg.input_max - cfg.input_min).cwiseInverse();
  const Mat24 Nx = em.N_x.asDiagonal();
  const Mat24 Nx_inv = em.N_x.cwiseInverse().asDiagonal();
  const Eigen::Matrix4d Nu_inv = em.N_u.cwiseInverse().asDiagonal();
  em.A_n = Nx * em.A * Nx_inv;
  for (const Mat24& Av : em.A_vertices) em.A_n_vertices.push_back(Nx * Av * Nx_inv);
  em.B_n = Nx * em.B * Nu_inv;
  em.D_n = Nx * em.D;
  return em;
}

}  // namespace tmpc
