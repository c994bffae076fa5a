// The offline synthesis pipeline.
#include "tmpc/synthesis/design.hpp"

#include <chrono>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "tmpc/model/reference.hpp"
#include "tmpc/sim/el_plant.hpp"
#include "tmpc/sim/perturbation.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

const char* const kStateNames[24] = {"x",         "y",         "z",         "phi",       "theta",     "psi",
                                     "gamma_1",   "gamma_2",   "alpha_r",   "alpha_l",   "x_dot",     "y_dot",
                                     "z_dot",     "phi_dot",   "theta_dot", "psi_dot",   "gamma_1_dot", "gamma_2_dot",
                                     "alpha_r_dot", "alpha_l_dot", "int_x",   "int_y",     "int_z",     "int_psi"};
const char* const kInputNames[4] = {"f_r", "f_l", "tau_r", "tau_l"};

SetSize set_size(const Box& b) {
  SetSize s;
  if (b.empty()) return s;
  s.one_norm_radius = b.one_norm_radius();
  s.volume = b.volume();
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// A numerical failure downstream of the config, named by the config section it came
/// from (a ConfigError, like the config's own errors).
template <class F>
auto in_section(const Config& cfg, const char* section, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const ConfigError&) {
    throw;
  } catch (const std::exception& e) {
    throw ConfigError(cfg.source + ": " + section + ": " + e.what());
  }
}

/// W from the config: W_u (a box, fractions of the state half-widths, i.e. directly
/// the normalized half-widths) plus W_d = D_z D (the force box on the load).
Zonotope uncertainty_box(const ControllerDesign& d) {
  const SynthesisSettings& s = d.cfg.synthesis;
  Zonotope w(Eigen::VectorXd::Zero(kNa), Eigen::MatrixXd(s.w_state_fraction.asDiagonal()));
  if ((s.w_disturbance.array() > 0.0).any()) {
    w = w.plus(Zonotope(Eigen::VectorXd::Zero(kNa), d.em.D_n * s.w_disturbance.asDiagonal()));
  }
  return w;
}

/// W from sampling: the one-step mismatch between perturbed nonlinear plants and the
/// nominal linear model, minus its value on the reference (that constant part is the
/// integrators' job), bounded by a box in normalized coordinates.
Zonotope uncertainty_sampled(const ControllerDesign& d, std::string& description) {
  const Config& cfg = d.cfg;
  const SynthesisSettings& s = cfg.synthesis;
  const TiltrotorModel model(cfg.vehicle);
  const HelixTrajectory traj(cfg.reference, model);
  std::mt19937_64 rng(cfg.perturbation.seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), time(0.0, cfg.simulation.duration);
  PerturbationSettings ps = cfg.perturbation;
  ps.fraction = s.w_sample_fraction;
  ps.distribution = "uniform";
  Eigen::VectorXd half = s.w_state_fraction;  // floor: the configured box
  const double T = cfg.sample_time;
  for (int k = 0; k < s.w_samples; ++k) {
    const VehicleParams p = apply_mass_scaling(cfg.vehicle, draw_mass_scaling(ps, k));
    ElPlant plant(p, DisturbanceSchedule{}, cfg.simulation.substep);
    const double t = time(rng);
    const ReferencePoint r0 = traj.at(t), r1 = traj.at(t + T);
    State20 xr0, xr1;
    xr0 << r0.q, r0.qd;
    xr1 << r1.q, r1.qd;
    const Eigen::Vector4d ur = feedforward(model, r0);
    // Error state drawn in the configured fraction of the state box.
    Vec24 e = Vec24::Zero();
    for (int i = 0; i < kNx; ++i) e(i) = s.w_sample_box * uni(rng) * cfg.state_error_max(i);
    auto step = [&](const Vec24& e0) {
      plant.reset(xr0 + e0.head<kNx>(), t);
      plant.advance(ur, T);
      return Eigen::Matrix<double, kNx, 1>(plant.state() - xr1);
    };
    // Mismatch at e and on the reference; their difference is the state-dependent part.
    const Eigen::Matrix<double, kNx, 1> w = step(e) - d.em.A.topLeftCorner<kNx, kNx>() * e.head<kNx>() - step(Vec24::Zero());
    half.head<kNx>() = half.head<kNx>().cwiseMax(d.em.N_x.head<kNx>().cwiseProduct(w).cwiseAbs());
  }
  std::ostringstream os;
  os << "sampled: " << s.w_samples << " one-step mismatches of plants with masses and inertias +-"
     << 100.0 * s.w_sample_fraction << " % in " << s.w_sample_box << " of the state box, centred on the reference";
  description = os.str();
  return Zonotope(Eigen::VectorXd::Zero(kNa), Eigen::MatrixXd(half.asDiagonal()));
}

/// Closed-loop matrices S_i = A_i + B K for the nominal model and every vertex.
std::vector<Eigen::MatrixXd> closed_loops(const ControllerDesign& d, const Eigen::MatrixXd& K) {
  std::vector<Eigen::MatrixXd> S;
  for (const Eigen::MatrixXd& A : d.vertices) S.push_back(A + d.em.B_n * K);
  return S;
}

RpiResult compute_tube(const ControllerDesign& d, const std::string& variant, const Eigen::MatrixXd& K,
                       const std::vector<Eigen::MatrixXd>& K_vertices, const Zonotope& W) {
  RpiSettings rs;
  rs.lambda = d.cfg.synthesis.rpi_lambda;
  const std::vector<Eigen::MatrixXd> S = closed_loops(d, K);
  const std::vector<Eigen::MatrixXd> vert(S.begin() + 1, S.end());
  if (variant == "lti") return rpi_lti(S[0], W, rs);
  if (variant == "lpv_thesis") {
    // Theorem 3.3: S_i with each vertex's own gain K_i.
    std::vector<Eigen::MatrixXd> Si;
    for (std::size_t i = 0; i < K_vertices.size(); ++i) Si.push_back(d.vertices[i + 1] + d.em.B_n * K_vertices[i]);
    return rpi_lpv_thesis(S[0], Si, W, rs);
  }
  return rpi_lpv_robust(S[0], vert, W, rs);
}

/// Tightened sets for a tube; empty sets are reported with the dimension.
void tighten(const ControllerDesign& d, const Eigen::MatrixXd& K, const Zonotope& Z, Box& x_bar, Box& u_bar) {
  x_bar = d.X.minus(Z);
  u_bar = d.U.minus(Z.map(K));
}

std::string empty_message(const Box& x_bar, const Box& u_bar) {
  const int ix = x_bar.first_empty_dimension();
  if (ix >= 0) return std::string("tightened state set X - Z is empty in dimension ") + kStateNames[ix];
  const int iu = u_bar.first_empty_dimension();
  if (iu >= 0) return std::string("tightened input set U - K Z is empty in dimension ") + kInputNames[iu];
  return "";
}

/// Largest s with non-empty X - sZ and U - sKZ, by bisection. With a zero-centred W
/// the tube of sW is s Z exactly (every construction here is linear in W), which the
/// evaluation uses; otherwise the tube is recomputed for every s.
double robustness_margin(const ControllerDesign& d, const std::string& variant, const Eigen::MatrixXd& K,
                         const std::vector<Eigen::MatrixXd>& K_vertices, const Zonotope& W, const Zonotope& Z,
                         std::string& method) {
  const bool linear = W.c.cwiseAbs().maxCoeff() == 0.0;
  method = linear ? "bisection on s, tube of s W = s Z (W centred)" : "bisection on s, tube recomputed";
  auto ok = [&](double s) {
    Zonotope Zs;
    if (linear) {
      Zs = Zonotope(Z.c * s, Z.G * s);
    } else {
      try {
        Zs = compute_tube(d, variant, K, K_vertices, Zonotope(W.c * s, W.G * s)).Z;
      } catch (const std::exception&) {
        return false;
      }
    }
    Box xb, ub;
    tighten(d, K, Zs, xb, ub);
    return !xb.empty() && !ub.empty();
  };
  if (!ok(0.0)) return 0.0;
  double lo = 0.0, hi = 1.0;
  while (ok(hi)) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e9) return hi;
  }
  for (int it = 0; it < 60 && hi - lo > 1e-6 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ok(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

ControllerDesign design_controller(const Config& cfg, const std::string& config_text, const DesignProgress& progress) {
  const auto t_start = Clock::now();
  auto say = [&](const std::string& m) {
    if (progress) progress(m);
  };
  ControllerDesign d;
  d.cfg = cfg;
  d.config_text = config_text;
  const SynthesisSettings& syn = cfg.synthesis;

  // Error model in normalized coordinates; weights transformed so the cost is kept:
  // x'Sigma x = x_n' N_x^-1 Sigma N_x^-1 x_n (the thesis' weights are physical: LQR
  // with them reproduces the spectral radius 0.9940 of research/tube_feasibility.md).
  auto t0 = Clock::now();
  say("linear error model along the helix");
  const TiltrotorModel model(cfg.vehicle);
  d.em = in_section(cfg, "reference (linearization and trim along the trajectory)", [&] { return build_error_model(cfg, model); });
  const Eigen::VectorXd nx_inv = d.em.N_x.cwiseInverse(), nu_inv = d.em.N_u.cwiseInverse();
  d.Sigma_rho_n = (cfg.state_weights.cwiseProduct(nx_inv).cwiseProduct(nx_inv)).asDiagonal();
  d.Sigma_lambda_n = (cfg.input_weights.cwiseProduct(nu_inv).cwiseProduct(nu_inv)).asDiagonal();
  d.vertices.push_back(d.em.A_n);
  for (const Mat24& A : d.em.A_n_vertices) d.vertices.push_back(A);
  d.X = Box::symmetric(Eigen::VectorXd::Ones(kNa));
  d.U = Box(d.em.N_u.cwiseProduct(d.em.input_error_min), d.em.N_u.cwiseProduct(d.em.input_error_max));
  d.seconds.error_model = since(t0);

  // Uncertainty set W.
  t0 = Clock::now();
  if (syn.w_source == "sampled") {
    say("sampling the model mismatch for W");
    d.W = uncertainty_sampled(d, d.w_description);
  } else {
    d.W = uncertainty_box(d);
    std::ostringstream os;
    os << "box: W_u = " << syn.w_state_fraction.maxCoeff() << " of each state's half-width per step";
    if ((syn.w_disturbance.array() > 0.0).any()) os << ", plus D_z times a force box of " << syn.w_disturbance.transpose() << " N";
    d.w_description = os.str();
  }
  d.seconds.uncertainty = since(t0);

  // Gains: LQR (also the fallback) and the two forms of Theorem 3.1.
  t0 = Clock::now();
  const LqrResult lqr = in_section(cfg, "weights (the LQR gain's Riccati equation)",
                                   [&] { return solve_dlqr(d.em.A_n, d.em.B_n, d.Sigma_rho_n, d.Sigma_lambda_n); });
  d.K_lqr = lqr.K;
  d.P_lqr = lqr.P;
  std::vector<std::string> names = {"lqr"};
  if (syn.compare_gains || syn.tube_gain == "lmi_thesis") names.push_back("lmi_thesis");
  if (syn.compare_gains || syn.tube_gain == "lmi_robust") names.push_back("lmi_robust");
  const Eigen::VectorXd u_max = d.U.lo.cwiseAbs().cwiseMin(d.U.hi);  // symmetric bound inside U
  auto lmi_problem = [&](LmiForm form, const std::vector<Eigen::MatrixXd>& A) {
    LmiGainProblem p;
    p.A = A;
    p.B = d.em.B_n;
    p.Q = d.Sigma_rho_n;
    p.R = d.Sigma_lambda_n;
    p.Hw = d.W.G;
    p.u_max = u_max;
    p.form = form;
    p.w_floor = syn.lmi_w_floor;
    if (syn.lmi_lambda != "search") p.lambda = std::stod(syn.lmi_lambda);
    return p;
  };
  const std::vector<Eigen::MatrixXd> lmi_vertices =
      syn.lmi_vertices ? d.vertices : std::vector<Eigen::MatrixXd>{d.em.A_n};
  for (const std::string& name : names) {
    const auto tg = Clock::now();
    GainDesign g;
    g.name = name;
    if (name == "lqr") {
      g.available = true;
      g.K = lqr.K;
      std::ostringstream os;
      os << "DARE residual " << lqr.residual << " after " << lqr.iterations << " doubling steps";
      g.message = os.str();
    } else {
      const LmiForm form = name == "lmi_thesis" ? LmiForm::Thesis : LmiForm::Robust;
      say(std::string("Theorem 3.1, ") + to_string(form) + " form, " + std::to_string(lmi_vertices.size()) +
          " vertices (CSDP)");
      const LmiGainProblem p = lmi_problem(form, lmi_vertices);
      g.lmi = syn.lmi_lambda == "search" ? solve_lmi_gain_line_search(p) : solve_lmi_gain(p);
      g.available = g.lmi.feasible;
      g.message = std::string(to_string(g.lmi.status)) + ": " + g.lmi.message;
      if (g.available) g.K = g.lmi.K;
      if (form == LmiForm::Robust && syn.lmi_certify_steps > 0) {
        // Largest scale s of W for which the robust form is feasible, by bisection on log s.
        say("largest W certified by the robust form (" + std::to_string(syn.lmi_certify_steps) + " SDPs)");
        double lo = g.available ? 1.0 : 1e-6, hi = g.available ? 1e4 : 1.0;
        bool lo_ok = g.available;
        for (int k = 0; k < syn.lmi_certify_steps; ++k) {
          const double mid = std::sqrt(lo * hi);
          LmiGainProblem q = p;
          q.Hw = p.Hw * mid;
          if (solve_lmi_gain(q).feasible) {
            lo = mid;
            lo_ok = true;
          } else {
            hi = mid;
          }
        }
        g.certified_w_scale = lo_ok ? lo : 0.0;
        g.refuted_w_scale = hi;
      }
    }
    if (g.available) {
      for (const Eigen::MatrixXd& A : d.vertices) g.vertex_spectral_radius.push_back(spectral_radius(A + d.em.B_n * g.K));
    }
    g.seconds = since(tg);
    d.gains.push_back(std::move(g));
  }
  for (std::size_t i = 0; i < d.gains.size(); ++i) {
    if (d.gains[i].name == syn.tube_gain) d.selected = static_cast<int>(i);
  }
  GainDesign& sel = d.gains[static_cast<std::size_t>(d.selected)];
  if (!sel.available) {
    throw ConfigError(cfg.source + ": synthesis.tube_gain: tube gain '" + syn.tube_gain +
                      "' does not exist (synthesis.lmi, its SDP): " + sel.message);
  }
  d.K = sel.K;
  // Per-vertex gains K_i of Theorem 3.3, from the selected family.
  for (std::size_t i = 1; i < d.vertices.size(); ++i) {
    if (syn.tube_gain == "lqr") {
      d.K_vertices.push_back(solve_dlqr(d.vertices[i], d.em.B_n, d.Sigma_rho_n, d.Sigma_lambda_n).K);
    } else if (syn.rpi_variant == "lpv_thesis") {
      say("Theorem 3.1 at vertex " + std::to_string(i));
      const LmiForm form = syn.tube_gain == "lmi_thesis" ? LmiForm::Thesis : LmiForm::Robust;
      const LmiGainResult r = solve_lmi_gain(lmi_problem(form, {d.vertices[i]}));
      d.K_vertices.push_back(r.feasible ? r.K : d.K);
    } else {
      d.K_vertices.push_back(d.K);  // not used by this variant
    }
  }
  d.L_terminal = syn.terminal_cost == "lmi" ? sel.lmi.L : d.P_lqr;
  if (syn.terminal_cost == "lmi" && !sel.lmi.feasible) {
    throw ConfigError(cfg.source + ": synthesis.terminal_cost: lmi needs an LMI tube gain (tube_gain is " +
                      syn.tube_gain + ")");
  }
  d.seconds.gains = since(t0);

  // Tubes of every gain (configured variant), tightened sets and margins.
  t0 = Clock::now();
  say("RPI zonotopes (" + syn.rpi_variant + ")");
  for (GainDesign& g : d.gains) {
    if (!g.available) continue;
    try {
      const std::vector<Eigen::MatrixXd> Kv = (&g == &sel) ? d.K_vertices : std::vector<Eigen::MatrixXd>(d.vertices.size() - 1, g.K);
      const RpiResult r = compute_tube(d, syn.rpi_variant, g.K, Kv, d.W);
      g.j = r.j;
      g.alpha = r.alpha;
      g.generators = r.Z.order();
      g.z_hull = r.Z.interval_hull();
      tighten(d, g.K, r.Z, g.x_bar, g.u_bar);
      g.tube_message = empty_message(g.x_bar, g.u_bar);
      g.tube_ok = g.tube_message.empty();
      std::string method;
      g.margin = robustness_margin(d, syn.rpi_variant, g.K, Kv, d.W, r.Z, method);
      if (&g == &sel) {
        d.tube = r;
        d.margin_method = method;
      }
    } catch (const std::exception& e) {
      g.tube_ok = false;
      g.tube_message = e.what();
    }
  }
  if (!sel.tube_ok) {
    throw ConfigError(cfg.source + ": synthesis.uncertainty and synthesis.rpi: the tube of gain '" + sel.name +
                      "': " + sel.tube_message + " (a smaller W or a wider constraints.state_error_max)");
  }
  d.x_bar = sel.x_bar;
  d.u_bar = sel.u_bar;
  d.margin = sel.margin;
  d.seconds.rpi = since(t0);

  // Independent invariance check and the variants side by side (Tables 5.1, 5.2).
  t0 = Clock::now();
  say("invariance checks");
  const std::vector<Eigen::MatrixXd> S = closed_loops(d, d.K);
  d.support_check = check_invariance_support(d.tube.Z, S, d.W, syn.verify_directions, 20240);
  for (const std::string& v : {std::string("lti"), std::string("lpv_thesis"), std::string("lpv_robust")}) {
    VariantComparison c;
    c.variant = v;
    try {
      const RpiResult r = v == syn.rpi_variant ? d.tube : compute_tube(d, v, d.K, d.K_vertices, d.W);
      Box xb, ub;
      tighten(d, d.K, r.Z, xb, ub);
      c.ok = true;
      c.j = r.j;
      c.alpha = r.alpha;
      c.z = set_size(r.Z.interval_hull());
      c.x_bar = set_size(xb);
      c.u_bar = set_size(ub);
      c.support_ratio = check_invariance_support(r.Z, S, d.W, std::min(200, syn.verify_directions), 7).worst_ratio;
      c.message = empty_message(xb, ub);
    } catch (const std::exception& e) {
      c.message = e.what();
    }
    d.variants.push_back(c);
  }
  d.seconds.checks = since(t0);

  // QP data.
  t0 = Clock::now();
  d.qp = in_section(cfg, "synthesis.horizon", [&] {
    return build_mpc_qp(d.em.A_n, d.em.B_n, d.Sigma_rho_n, d.Sigma_lambda_n, d.L_terminal, d.x_bar, d.u_bar,
                        syn.horizon, syn.control_horizon);
  });
  d.seconds.qp = since(t0);
  d.seconds.total = since(t_start);
  return d;
}

}  // namespace tmpc
