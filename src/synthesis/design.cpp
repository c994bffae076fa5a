// The offline synthesis pipeline.
#include "tmpc/synthesis/design.hpp"

#include <chrono>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "tmpc/model/perturbation.hpp"
#include "tmpc/model/reference.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

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
  const int n = d.em.n;
  Zonotope w(Eigen::VectorXd::Zero(n), Eigen::MatrixXd(s.w_state_fraction.asDiagonal()));
  if ((s.w_disturbance.array() > 0.0).any()) {
    w = w.plus(Zonotope(Eigen::VectorXd::Zero(n), d.em.D_n * s.w_disturbance.asDiagonal()));
  }
  return w;
}

/// W from sampling (tiltrotor): the one-step mismatch between perturbed nonlinear
/// models and the nominal linear model at trims drawn over the envelope, minus its
/// value on the reference (that constant part is the integrators' job), bounded by a
/// box in normalized coordinates. One step is RK4 sub-steps of the model (rk4_step).
Zonotope uncertainty_sampled(const ControllerDesign& d, std::string& description) {
  const Config& cfg = d.cfg;
  const SynthesisSettings& s = cfg.synthesis;
  const TiltrotorModel model(cfg.vehicle);
  const EnvelopeSettings env = resolve_envelope(cfg);
  std::mt19937_64 rng(s.w_seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0), unit(0.0, 1.0);
  PerturbationSettings ps;
  ps.fraction = s.w_sample_fraction;
  ps.distribution = "uniform";
  ps.seed = s.w_seed;
  Eigen::VectorXd half = s.w_state_fraction;  // floor: the configured box
  const double T = cfg.sample_time;
  const long substeps = std::max(1L, std::lround(T / cfg.simulation.substep));
  const double h = T / static_cast<double>(substeps);
  for (int k = 0; k < s.w_samples; ++k) {
    const TiltrotorModel plant(apply_mass_scaling(cfg.vehicle, draw_mass_scaling(ps, k)));
    Eigen::Vector3d sigma;
    for (int i = 0; i < 3; ++i) sigma(i) = env.acceleration_min(i) + unit(rng) * (env.acceleration_max(i) - env.acceleration_min(i));
    const Trim trim = solve_trim(model, sigma, Eigen::Vector3d::Zero(), env.yaw, d.em.equilibrium);
    Vec10 q = d.em.equilibrium.q();
    q(kPsi) = env.yaw;
    q.segment<2>(kPhi) = trim.attitude;
    q.segment<4>(kGamma1) = trim.angles;
    State20 xr;
    xr << q, Vec10::Zero();
    // Error state drawn in the configured fraction of the state box.
    State20 e;
    for (int i = 0; i < kNx; ++i) e(i) = s.w_sample_box * uni(rng) * cfg.state_error_max(i);
    auto step = [&](const State20& x0) {
      State20 x = x0;
      for (long j = 0; j < substeps; ++j) x = rk4_step(plant, x, trim.u, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), h);
      return x;
    };
    // Mismatch at e and on the reference; their difference is the state-dependent part
    // (the reference's own motion over the period cancels).
    const State20 w = step(xr + e) - d.em.A.topLeftCorner(kNx, kNx) * e - step(xr);
    half.head(kNx) = half.head(kNx).cwiseMax(d.em.N_x.head(kNx).cwiseProduct(w).cwiseAbs());
  }
  std::ostringstream os;
  os << "sampled: " << s.w_samples << " one-step mismatches of models with masses and inertias +-"
     << 100.0 * s.w_sample_fraction << " % in " << s.w_sample_box << " of the state box, at trims over the envelope";
  description = os.str();
  return Zonotope(Eigen::VectorXd::Zero(d.em.n), Eigen::MatrixXd(half.asDiagonal()));
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

std::string empty_message(const ControllerDesign& d, const Box& x_bar, const Box& u_bar) {
  const int ix = x_bar.first_empty_dimension();
  if (ix >= 0) return "tightened state set X - Z is empty in dimension " + d.state_names[static_cast<std::size_t>(ix)];
  const int iu = u_bar.first_empty_dimension();
  if (iu >= 0) return "tightened input set U - K Z is empty in dimension " + d.input_names[static_cast<std::size_t>(iu)];
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

/// The Kalman filter of the config's `estimation` section (estimator.hpp): measured
/// rows, residual channels on the angular-rate rows, covariances in normalized units.
KalmanDesign kalman_for(const ControllerDesign& d) {
  const EstimationSettings& e = d.cfg.estimation;
  const std::vector<StateKind> kinds = d.cfg.state_kinds();
  const int p = d.em.measured, nd = static_cast<int>(d.em.D_n.cols());
  std::vector<int> rows, rates;
  for (int i = 0; i < p; ++i) {
    const StateKind k = kinds[static_cast<std::size_t>(i)];
    if (e.measured == "all" || k != StateKind::Velocity) rows.push_back(i);
    if (k == StateKind::AngularRate) rates.push_back(i);
  }
  Eigen::MatrixXd E_c = Eigen::MatrixXd::Zero(p, static_cast<Eigen::Index>(rates.size()));
  for (std::size_t j = 0; j < rates.size(); ++j) E_c(rates[j], static_cast<Eigen::Index>(j)) = 1.0;
  const int nc = static_cast<int>(rates.size()), na = p + nd + nc;
  Eigen::VectorXd q(na);
  q.head(p).setConstant(e.process_state_fraction * e.process_state_fraction);
  q.segment(p, nd).setConstant(e.process_force * e.process_force);
  q.tail(nc).setConstant(e.process_residual * e.process_residual);
  Eigen::VectorXd r(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const int i = rows[j];
    const double sn = e.noise[static_cast<std::size_t>(group_of(kinds[static_cast<std::size_t>(i)]))] * d.em.N_x(i);
    r(static_cast<Eigen::Index>(j)) = sn * sn;
  }
  return design_kalman(d.em.A_n.topLeftCorner(p, p), d.em.B_n.topRows(p), d.em.D_n.topRows(p), E_c, rows,
                       q.asDiagonal(), r.asDiagonal());
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
  say(cfg.model == ModelKind::Tiltrotor ? "linear error model over the trajectory envelope" : "linear model");
  d.state_names = cfg.state_names();
  d.input_names = cfg.input_names();
  d.envelope = cfg.model == ModelKind::Tiltrotor ? resolve_envelope(cfg) : cfg.envelope;
  d.em = in_section(cfg, "envelope (linearization and trim over the envelope)", [&] { return build_error_model(cfg); });
  const Eigen::VectorXd nx_inv = d.em.N_x.cwiseInverse(), nu_inv = d.em.N_u.cwiseInverse();
  d.Sigma_rho_n = (cfg.state_weights.cwiseProduct(nx_inv).cwiseProduct(nx_inv)).asDiagonal();
  d.Sigma_lambda_n = (cfg.input_weights.cwiseProduct(nu_inv).cwiseProduct(nu_inv)).asDiagonal();
  const Eigen::VectorXd rate = cfg.input_rate_weights.size() == nu_inv.size() ? cfg.input_rate_weights : Eigen::VectorXd::Zero(nu_inv.size());
  d.Sigma_delta_n = (rate.cwiseProduct(nu_inv).cwiseProduct(nu_inv)).asDiagonal();
  d.vertices.push_back(d.em.A_n);
  for (const Eigen::MatrixXd& A : d.em.A_n_vertices) d.vertices.push_back(A);
  d.X = Box::symmetric(Eigen::VectorXd::Ones(d.em.n));
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
  // The LQR tube gain: the same DARE with its own input weights (synthesis.lqr_input_scale
  // times lambda; a softer gain passes less sensor noise to the inputs).
  const Eigen::MatrixXd R_tube = syn.lqr_input_scale.asDiagonal() * d.Sigma_lambda_n;
  const LqrResult tube_lqr = (syn.lqr_input_scale.array() == 1.0).all()
                                 ? lqr
                                 : in_section(cfg, "synthesis.lqr_input_scale", [&] { return solve_dlqr(d.em.A_n, d.em.B_n, d.Sigma_rho_n, R_tube); });
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
      g.K = tube_lqr.K;
      std::ostringstream os;
      os << "DARE residual " << tube_lqr.residual << " after " << tube_lqr.iterations << " doubling steps";
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
      d.K_vertices.push_back(solve_dlqr(d.vertices[i], d.em.B_n, d.Sigma_rho_n, R_tube).K);
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
      g.tube_message = empty_message(d, g.x_bar, g.u_bar);
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
      c.message = empty_message(d, xb, ub);
    } catch (const std::exception& e) {
      c.message = e.what();
    }
    d.variants.push_back(c);
  }
  d.seconds.checks = since(t0);

  // State estimation and the output-feedback tube.
  t0 = Clock::now();
  d.x_bar_state_feedback = d.x_bar;
  d.u_bar_state_feedback = d.u_bar;
  if (cfg.estimation.observer == "kalman") {
    say("Kalman filter");
    d.kf = in_section(cfg, "estimation", [&] { return kalman_for(d); });
    d.kalman = true;
    {
      // How much sensor noise the tube gain passes to the inputs, for softer and harder
      // input weights than the design's (the report's trade-off; the selected gain is
      // the config's synthesis.lqr_input_scale).
      const int p = d.kf.p;
      const Eigen::MatrixXd post = ((Eigen::MatrixXd::Identity(d.kf.P.rows(), d.kf.P.cols()) - d.kf.L * d.kf.C) * d.kf.P).topLeftCorner(p, p);
      for (double f : {0.1, 1.0, 10.0, 100.0}) {
        ControllerDesign::NoiseTradeoff t;
        t.scale = f;
        const Eigen::MatrixXd R = f * syn.lqr_input_scale.asDiagonal() * d.Sigma_lambda_n;
        const Eigen::MatrixXd K = solve_dlqr(d.em.A_n, d.em.B_n, d.Sigma_rho_n, R).K;
        const Eigen::MatrixXd Kp = K.leftCols(p);
        t.input_noise_std = (Kp * post * Kp.transpose()).diagonal().cwiseSqrt().cwiseQuotient(d.em.N_u);
        t.spectral_radius = spectral_radius(d.em.A_n + d.em.B_n * K);
        try {
          const std::vector<Eigen::MatrixXd> Kv(d.vertices.size() - 1, K);
          const RpiResult r = compute_tube(d, syn.rpi_variant, K, Kv, d.W);
          std::string method;
          t.margin = robustness_margin(d, syn.rpi_variant, K, Kv, d.W, r.Z, method);
        } catch (const std::exception&) {
          t.margin = 0.0;
        }
        d.noise_tradeoff.push_back(t);
      }
    }
    {  // computed for the report always, applied when configured
      say("output-feedback tube (estimation error and control tube)");
      const EstimationSettings& e = cfg.estimation;
      const Eigen::Index p = d.kf.p, nd = d.em.D_n.cols(), nc = d.kf.E_c.cols();
      Eigen::VectorXd W_a(p + nd + nc);
      W_a.head(p) = d.W.radius().head(p);
      W_a.segment(p, nd).setConstant(e.force_rate_bound);
      W_a.tail(nc).setConstant(e.residual_rate_bound);
      const Eigen::VectorXd V = e.noise_bound_sigmas * d.kf.R.diagonal().cwiseSqrt();
      const std::vector<Eigen::MatrixXd> loops =
          syn.rpi_variant == "lpv_robust" ? closed_loops(d, d.K) : std::vector<Eigen::MatrixXd>{closed_loops(d, d.K)[0]};
      // Not applied, it is a figure of the report: a set that cannot be computed (an
      // estimation loop too slow for the RPI series) is said there, not fatal.
      try {
        d.of = in_section(cfg, "estimation.output_feedback_tube",
                          [&] { return output_feedback_tube(d.kf, loops, d.K, W_a, V, d.X, d.U, syn.rpi_lambda); });
        d.of_computed = true;
      } catch (const ConfigError& ex) {
        if (e.output_feedback_tube) throw;
        d.of_message = ex.what();
      }
    }
    if (d.of_computed) {  // the configured form applied, or an error when its sets are empty
      const EstimationSettings& e = cfg.estimation;
      const bool gaussian = e.gaussian_noise();
      const std::string msg = gaussian ? empty_message(d, d.of.x_bar_gaussian, d.of.u_bar_gaussian)
                                       : empty_message(d, d.of.x_bar, d.of.u_bar);
      if (e.output_feedback_tube && !msg.empty()) {
        std::ostringstream os;
        os << cfg.source << ": estimation: the output-feedback tube (" << e.output_feedback_noise << " noise) at "
           << e.noise_bound_sigmas << " standard deviations of the measurement noise: " << msg
           << " (the sets hold up to " << (gaussian ? d.of.noise_margin_gaussian : d.of.noise_margin)
           << " times that noise)";
        throw ConfigError(os.str());
      }
      if (e.output_feedback_tube) {
        d.output_feedback = true;
        if (gaussian) {
          d.tube.Z = d.of.Z_W.plus(Zonotope(Eigen::VectorXd::Zero(d.of.delta_sigmas_v.size()),
                                            Eigen::MatrixXd(d.of.delta_sigmas_v.asDiagonal())));
          d.x_bar = d.of.x_bar_gaussian;
          d.u_bar = d.of.u_bar_gaussian;
        } else {
          d.tube.Z = d.of.Z_c;
          d.x_bar = d.of.x_bar;
          d.u_bar = d.of.u_bar;
        }
      }
    }
  }
  d.seconds.estimation = since(t0);

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
