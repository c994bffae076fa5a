// Linear error model over the envelope, integrals, discretization, normalization
// (thesis 5.2).
#include "tmpc/model/error_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "tmpc/model/reference.hpp"
#include "trajectory_yaml.hpp"

namespace tmpc {

Mat20 LpvModel::at(const Eigen::Vector3d& sigma) const {
  Mat20 A = A0;
  for (int i = 0; i < 3; ++i) A += sigma(i) * A_sigma[static_cast<std::size_t>(i)];
  return A;
}

void augment_with_integrals(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& D,
                            const std::vector<int>& integrated, Eigen::MatrixXd& Aa, Eigen::MatrixXd& Ba,
                            Eigen::MatrixXd& Da) {
  const Eigen::Index p = A.rows(), k = static_cast<Eigen::Index>(integrated.size()), n = p + k;
  Aa = Eigen::MatrixXd::Zero(n, n);
  Ba = Eigen::MatrixXd::Zero(n, B.cols());
  Da = Eigen::MatrixXd::Zero(n, D.cols());
  Aa.topLeftCorner(p, p) = A;
  // Integral rows: d/dt int(e_i) = e_i (C of (5.5)).
  for (Eigen::Index i = 0; i < k; ++i) Aa(p + i, integrated[static_cast<std::size_t>(i)]) = 1.0;
  Ba.topRows(p) = B;
  Da.topRows(p) = D;
}

void discretize(const Eigen::MatrixXd& Ac, const Eigen::MatrixXd& Bc, const Eigen::MatrixXd& Dc, double T,
                Discretization method, Eigen::MatrixXd& A, Eigen::MatrixXd& B, Eigen::MatrixXd& D) {
  const Eigen::Index n = Ac.rows(), m = Bc.cols(), nd = Dc.cols();
  if (method == Discretization::Euler) {
    // Thesis (5.8) with the sign of E1 corrected: A_z = I + A_a T.
    A = Eigen::MatrixXd::Identity(n, n) + Ac * T;
    B = Bc * T;
    D = Dc * T;
    return;
  }
  // Exact zero-order hold: expm([A B D; 0 0 0] T) = [A_z B_z D_z; 0 I 0; 0 0 I].
  Eigen::MatrixXd blk = Eigen::MatrixXd::Zero(n + m + nd, n + m + nd);
  blk.topLeftCorner(n, n) = Ac * T;
  blk.block(0, n, n, m) = Bc * T;
  blk.block(0, n + m, n, nd) = Dc * T;
  const Eigen::MatrixXd e = blk.exp();
  A = e.topLeftCorner(n, n);
  B = e.block(0, n, n, m);
  D = e.block(0, n + m, n, nd);
}

namespace {

State20 stack(const Vec10& q, const Vec10& qd) {
  State20 x;
  x << q, qd;
  return x;
}

std::string vec_text(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os << "(" << v(0) << ", " << v(1) << ", " << v(2) << ")";
  return os.str();
}

/// The trajectory and the sampled span of a scenario file named by the envelope.
struct EnvelopeSample {
  Eigen::Vector3d a_min = Eigen::Vector3d::Constant(1e300), a_max = Eigen::Vector3d::Constant(-1e300);
  double speed = 0.0, yaw_min = 1e300, yaw_max = -1e300, yaw_rate = 0.0;
};

/// The span of a scenario's trajectory; accelerations in the design's frame of `e`.
EnvelopeSample sample_scenario(const std::string& path, const std::string& what, const EnvelopeSettings& e) {
  std::string text;
  try {
    text = read_config_file(path, "scenario");
  } catch (const ConfigError& e) {
    throw ConfigError(what + ": " + e.what());
  }
  detail::Section root(detail::load_single_document(text, path), "", path);
  const std::unique_ptr<Trajectory> t = detail::trajectory_from(root.section("trajectory"), detail::folder_of(path));
  double span = std::isfinite(t->duration()) ? t->duration() : 100.0;
  if (root.has("duration")) span = std::min(std::isfinite(t->duration()) ? t->duration() : 1e300, root.positive("duration"));
  EnvelopeSample s;
  for (double tt = 0.0; tt <= span + 1e-9; tt += 0.005) {
    const TrajectoryPoint p = t->at(tt);
    const Eigen::Vector3d a = e.in_design_frame(p.a, p.psi);
    s.a_min = s.a_min.cwiseMin(a);
    s.a_max = s.a_max.cwiseMax(a);
    s.speed = std::max(s.speed, p.v.norm());
    s.yaw_min = std::min(s.yaw_min, p.psi);
    s.yaw_max = std::max(s.yaw_max, p.psi);
    s.yaw_rate = std::max(s.yaw_rate, std::abs(p.psi_d));
  }
  return s;
}

ErrorModel linear_error_model(const Config& cfg) {
  ErrorModel em;
  const LinearModelSpec& l = cfg.linear;
  em.measured = static_cast<int>(l.A.rows());
  em.integrated = l.integrated;
  augment_with_integrals(l.A, l.B, l.D, l.integrated, em.A_c, em.B_c, em.D_c);
  em.u_r_min = em.u_r_max = Eigen::VectorXd::Zero(l.B.cols());  // regulation to the origin
  return em;
}

ErrorModel tiltrotor_error_model(const Config& cfg) {
  ErrorModel em;
  const EnvelopeSettings env = resolve_envelope(cfg);
  const TiltrotorModel model(cfg.vehicle);
  em.measured = kNx;
  em.integrated = cfg.integrated();
  em.equilibrium = solve_hover_equilibrium(model, env.yaw);
  const bool trim = cfg.attitude == ReferenceAttitude::Trim;
  const Eigen::Vector3d no_d = Eigen::Vector3d::Zero();
  LpvModel& lpv = em.lpv;
  lpv.sigma_min = env.acceleration_min;
  lpv.sigma_max = env.acceleration_max;

  // The reference at acceleration sigma (zero velocity: with no translational
  // friction the velocity enters neither the trim nor the linearization's A through
  // the translational coordinates), its linearization and feedforward.
  Trim last = trim_start(em.equilibrium);
  auto reference_at = [&](const Eigen::Vector3d& sigma, Eigen::Vector4d& u) {
    ReferencePoint r;
    r.q = em.equilibrium.q();
    r.q(kPsi) = env.yaw;
    r.qdd.head<3>() = sigma;
    if (trim) {
      try {
        last = solve_trim(model, sigma, Eigen::Vector3d::Zero(), env.yaw, trim_start(em.equilibrium));
      } catch (const std::exception& e) {
        throw ConfigError(cfg.source + ": envelope: no trim at the acceleration " + vec_text(sigma) +
                          " m/s^2 (" + e.what() + "): the envelope is beyond what the vehicle can fly");
      }
      r.q.segment<2>(kPhi) = last.attitude;
      r.q.segment<4>(kGamma1) = last.angles;
      u = last.u;
    } else {
      u = feedforward(model, r);  // exactly affine in sigma
    }
    return r;
  };
  auto linear_at = [&](const Eigen::Vector3d& sigma) {
    Eigen::Vector4d u;
    const ReferencePoint r = reference_at(sigma, u);
    return model.linearize(stack(r.q, r.qd), u, no_d);
  };

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
  // The feedforward's range and the affinity of A over a grid of the box.
  em.u_r_min = Eigen::VectorXd::Constant(kNu, 1e300);
  em.u_r_max = Eigen::VectorXd::Constant(kNu, -1e300);
  const int g = cfg.error_model.envelope_grid;
  const double a0 = lpv.A0.norm();
  double worst_abs = 0.0, worst_var = 0.0, worst_sigma = 0.0, worst_b = 0.0;
  for (int ix = 0; ix < g; ++ix) {
    for (int iy = 0; iy < g; ++iy) {
      for (int iz = 0; iz < g; ++iz) {
        const Eigen::Vector3d f(ix / double(g - 1), iy / double(g - 1), iz / double(g - 1));
        const Eigen::Vector3d sigma = lpv.sigma_min + f.cwiseProduct(lpv.sigma_max - lpv.sigma_min);
        Eigen::Vector4d u;
        const ReferencePoint r = reference_at(sigma, u);
        em.u_r_min = em.u_r_min.cwiseMin(u);
        em.u_r_max = em.u_r_max.cwiseMax(u);
        const Linearization l = model.linearize(stack(r.q, r.qd), u, no_d);
        const Mat20 A_lpv = lpv.at(sigma);
        worst_abs = std::max(worst_abs, (l.A - A_lpv).norm());
        worst_var = std::max(worst_var, (l.A - lpv.A0).norm());
        worst_sigma = std::max(worst_sigma, (A_lpv - lpv.A0).norm());
        worst_b = std::max(worst_b, (l.B - lpv.B).norm());
      }
    }
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
  augment_with_integrals(lpv.A0, lpv.B, lpv.D, em.integrated, em.A_c, em.B_c, em.D_c);
  for (const Eigen::Vector3d& s : lpv.vertex_sigma) {
    Eigen::MatrixXd Ac, Bc, Dc, Ad, Bd, Dd;
    augment_with_integrals(lpv.at(s), lpv.B, lpv.D, em.integrated, Ac, Bc, Dc);
    discretize(Ac, Bc, Dc, cfg.sample_time, cfg.error_model.discretization, Ad, Bd, Dd);
    em.A_vertices.push_back(Ad);
  }
  return em;
}

}  // namespace

EnvelopeSettings resolve_envelope(const Config& cfg) {
  EnvelopeSettings e = cfg.envelope;
  if (e.trajectories.empty()) return e;
  const bool configured_box = (e.acceleration_max - e.acceleration_min).cwiseAbs().maxCoeff() > 0.0 || e.speed_max > 0.0;
  EnvelopeSample all;
  for (const std::string& file : e.trajectories) {
    const std::string path = !file.empty() && file[0] == '/' ? file : detail::folder_of(cfg.source) + file;
    const EnvelopeSample s = sample_scenario(path, cfg.source + ": envelope.trajectories", e);
    if (configured_box) {
      for (int i = 0; i < 3; ++i) {
        if (s.a_min(i) < e.acceleration_min(i) - 1e-9 || s.a_max(i) > e.acceleration_max(i) + 1e-9) {
          throw ConfigError(cfg.source + ": envelope.acceleration_min/max: the trajectory of " + path +
                            " accelerates to [" + std::to_string(s.a_min(i)) + ", " + std::to_string(s.a_max(i)) +
                            "] m/s^2 along axis " + std::to_string(i) + ", outside the configured box");
        }
      }
      if (s.speed > e.speed_max + 1e-9) {
        throw ConfigError(cfg.source + ": envelope.speed_max: the trajectory of " + path + " reaches " +
                          std::to_string(s.speed) + " m/s");
      }
    }
    if (e.any_yaw()) {
      if (s.yaw_rate > e.yaw_rate_max + 1e-9) {
        throw ConfigError(cfg.source + ": envelope.yaw_rate_max: the trajectory of " + path + " turns at " +
                          std::to_string(s.yaw_rate) + " rad/s, above " + std::to_string(e.yaw_rate_max));
      }
    } else if (s.yaw_min < e.yaw - e.yaw_tolerance - 1e-9 || s.yaw_max > e.yaw + e.yaw_tolerance + 1e-9) {
      throw ConfigError(cfg.source + ": envelope.yaw: the trajectory of " + path + " flies at a yaw of [" +
                        std::to_string(s.yaw_min) + ", " + std::to_string(s.yaw_max) + "] rad, outside " +
                        std::to_string(e.yaw) + " +- " + std::to_string(e.yaw_tolerance));
    }
    all.a_min = all.a_min.cwiseMin(s.a_min);
    all.a_max = all.a_max.cwiseMax(s.a_max);
    all.speed = std::max(all.speed, s.speed);
  }
  if (!configured_box) {
    const Eigen::Vector3d mid = 0.5 * (all.a_min + all.a_max), half = 0.5 * (all.a_max - all.a_min);
    e.acceleration_min = mid - (1.0 + e.margin) * half;
    e.acceleration_max = mid + (1.0 + e.margin) * half;
    e.speed_max = (1.0 + e.margin) * all.speed;
  }
  return e;
}

ErrorModel build_error_model(const Config& cfg) {
  ErrorModel em = cfg.model == ModelKind::Tiltrotor ? tiltrotor_error_model(cfg) : linear_error_model(cfg);
  em.sample_time = cfg.sample_time;
  em.discretization = cfg.error_model.discretization;
  em.n = static_cast<int>(em.A_c.rows());
  em.m = static_cast<int>(em.B_c.cols());
  em.nd = static_cast<int>(em.D_c.cols());
  discretize(em.A_c, em.B_c, em.D_c, em.sample_time, em.discretization, em.A, em.B, em.D);
  if (cfg.model == ModelKind::Linear) em.A_vertices.clear();

  // Input box in error coordinates: must hold for every u_r over the envelope.
  em.input_error_min = cfg.input_min - em.u_r_max;
  em.input_error_max = cfg.input_max - em.u_r_min;
  for (int i = 0; i < em.m; ++i) {
    if (!(em.input_error_max(i) > 0.0 && em.input_error_min(i) < 0.0)) {
      throw ConfigError(cfg.source + ": constraints.input_min/max[" + std::to_string(i) + "]: the feedforward over the "
                        "envelope spans [" + std::to_string(em.u_r_min(i)) + ", " + std::to_string(em.u_r_max(i)) +
                        "], which leaves no room for feedback inside [" + std::to_string(cfg.input_min(i)) + ", " +
                        std::to_string(cfg.input_max(i)) + "]");
    }
  }

  // Normalization (5.10)-(5.11): the state error box and the input range become unit boxes.
  em.N_x = cfg.state_error_max.cwiseInverse();
  em.N_u = 2.0 * (cfg.input_max - cfg.input_min).cwiseInverse();
  const Eigen::MatrixXd Nx = em.N_x.asDiagonal();
  const Eigen::MatrixXd Nx_inv = em.N_x.cwiseInverse().asDiagonal();
  const Eigen::MatrixXd Nu_inv = em.N_u.cwiseInverse().asDiagonal();
  em.A_n = Nx * em.A * Nx_inv;
  for (const Eigen::MatrixXd& Av : em.A_vertices) em.A_n_vertices.push_back(Nx * Av * Nx_inv);
  em.B_n = Nx * em.B * Nu_inv;
  em.D_n = Nx * em.D;
  return em;
}

}  // namespace tmpc
