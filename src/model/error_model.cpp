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
  const HelixTrajectory traj(cfg.reference, model);
  em.equilibrium = traj.equilibrium();
  const Eigen::Vector3d no_d = Eigen::Vector3d::Zero();
  const bool trim = cfg.reference.attitude == ReferenceAttitude::Trim;

  // Linearization at the reference attitude for acceleration sigma, zero velocity.
  auto linear_at = [&](const Eigen::Vector3d& sigma) {
    ReferencePoint r;
    r.q = em.equilibrium.q();
    r.q(kPsi) = cfg.reference.yaw;
    r.qdd.head<3>() = sigma;
    Eigen::Vector4d u;
    if (trim) {
      const Trim t = solve_trim(model, sigma, Eigen::Vector3d::Zero(), cfg.reference.yaw, em.equilibrium);
      r.q.segment<2>(kPhi) = t.attitude;
      r.q.segment<4>(kGamma1) = t.angles;
      u = t.u;
    } else {
      u = feedforward(model, r);  // exactly affine in sigma
    }
    return model.linearize(stack(r.q, r.qd), u, no_d);
  };

  // Sample the mission: sigma's box and u_r's range.
  const double step = cfg.error_model.lpv_sample_step;
  const int samples = std::max(1, static_cast<int>(std::floor(cfg.simulation.duration / step + 1e-9))) + 1;
  std::vector<ReferencePoint> points;
  std::vector<Eigen::Vector4d> inputs;
  LpvModel& lpv = em.lpv;
  lpv.sigma_min.setConstant(1e300);
  lpv.sigma_max.setConstant(-1e300);
  em.u_r_min.setConstant(1e300);
  em.u_r_max.setConstant(-1e300);
  for (int k = 0; k < samples; ++k) {
    const ReferencePoint r = traj.at(std::min(k * step, cfg.simulation.duration));
    const Eigen::Vector4d ur = feedforward(model, r);
    em.u_r_min = em.u_r_min.cwiseMin(ur);
    em.u_r_max = em.u_r_max.cwiseMax(ur);
    lpv.sigma_min = lpv.sigma_min.cwiseMin(r.sigma());
    lpv.sigma_max = lpv.sigma_max.cwiseMax(r.sigma());
    points.push_back(r);
    inputs.push_back(ur);
  }

  // A_0 at sigma = 0, A_i the secant over sigma_i's range (exact for an affine A).
  const Linearization l0 = linear_at(Eigen::Vector3d::Zero());
  lpv.A0 = l0.A;
  lpv.B = l0.B;
  lpv.D = l0.D;
  lpv.A_sigma.assign(3, Mat20::Zero());
  for (int i = 0; i < 3; ++i) {
    const double lo = lpv.sigma_min(i), hi = lpv.sigma_max(i);
    if (hi - lo > 1e-12) {
      lpv.A_sigma[static_cast<std::size_t>(i)] =
          (linear_at(hi * Eigen::Vector3d::Unit(i)).A - linear_at(lo * Eigen::Vector3d::Unit(i)).A) / (hi - lo);
    }
  }

  // How affine the true A(t) (with the reference velocity) is, and how constant B is.
  const double a0 = lpv.A0.norm();
  double worst_abs = 0.0, worst_var = 0.0, worst_sigma = 0.0, worst_b = 0.0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const ReferencePoint& r = points[k];
    const Linearization l = model.linearize(stack(r.q, r.qd), inputs[k], no_d);
    const Mat20 A_lpv = lpv.at(r.sigma());
    worst_abs = std::max(worst_abs, (l.A - A_lpv).norm());
    worst_var = std::max(worst_var, (l.A - lpv.A0).norm());
    worst_sigma = std::max(worst_sigma, (A_lpv - lpv.A0).norm());
    worst_b = std::max(worst_b, (l.B - lpv.B).norm());
  }
  lpv.affinity_residual = worst_abs / a0;
  lpv.affinity_residual_relative = worst_var > 0.0 ? worst_abs / worst_var : 0.0;
  lpv.sigma_part = worst_sigma / a0;
  lpv.b_variation = worst_b / lpv.B.norm();
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
