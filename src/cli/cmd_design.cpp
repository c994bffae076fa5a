// Offline synthesis commands:
//   tmpc design --config FILE --out FILE.tmpc [--report FILE.json]
//   tmpc inspect FILE.tmpc [--json]
//   tmpc export-qp --controller FILE.tmpc --x0 "v1,...,v24" --out qp.json
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/solvers/soft_penalty.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/design.hpp"
#include "tmpc/synthesis/json_rows.hpp"

namespace tmpc::cli {

namespace {


struct DesignOptions {
  std::string config = "config/tiltrotor.yaml";
  std::string out;
  std::string report;
  bool explicit_law = false;
};

/// weights.input_rate as designed (physical: Sigma_delta's diagonal times N_u^2; zeros: none).
std::vector<double> input_rate_weights(const ControllerArtifact& a) {
  std::vector<double> w(static_cast<std::size_t>(a.m), 0.0);
  if (a.Sigma_delta.size() == 0) return w;
  for (int i = 0; i < a.m; ++i) w[static_cast<std::size_t>(i)] = a.Sigma_delta(i, i) * a.N_u(i) * a.N_u(i);
  return w;
}

void run_design(const DesignOptions& o) {
  const std::string text = read_config_text(o.config);
  const Config cfg = load_config_from_string(text, o.config);
  const ControllerDesign d = design_controller(cfg, text, [](const std::string& m) {
    std::fprintf(stderr, "tmpc design: %s ...\n", m.c_str());
  });
  ControllerArtifact a = make_artifact(d);
  const SoftPenaltyCalibration soft = apply_soft_penalty(a, cfg.soft_constraints.safety_factor);
  // The offset-free law needs the steady state of every force on the load: checked
  // here (a clear error), not first on the vehicle.
  DisturbanceTarget target;
  if (cfg.tube_law.offset_free) target = a.disturbance_target();
  save_artifact(a, o.out);
  if (o.explicit_law) {
    const ExplicitLaw law = build_explicit_law(a, explicit_options_from(cfg.explicit_mpc));
    save_explicit(law, explicit_path_for(o.out));
    print_explicit_summary(law, explicit_path_for(o.out));
  }
  if (!o.report.empty()) {
    std::ofstream r(o.report);
    if (!r) throw std::runtime_error(o.report + ": cannot write");
    nlohmann::json j = nlohmann::json::parse(design_report_json(d));
    j["soft_constraints"] = {{"enabled", a.soft_constraints},
                             {"penalty", a.soft_penalty},
                             {"calibrated", soft.samples > 0},
                             {"largest_multiplier_sum", soft.largest_multiplier_sum},
                             {"samples", soft.samples}};
    j["input_rate_weights"] = input_rate_weights(a);
    r << j.dump(2) << "\n";
  }
  const GainDesign& g = d.gains[static_cast<std::size_t>(d.selected)];
  std::printf("design of %s in %.1f s (error model %.1f, W %.1f, gains %.1f, tubes and margins %.1f, checks %.1f)\n",
              o.config.c_str(), d.seconds.total, d.seconds.error_model, d.seconds.uncertainty, d.seconds.gains,
              d.seconds.rpi, d.seconds.checks);
  std::printf("W: %s\n", d.w_description.c_str());
  std::printf("gains (tube variant %s):\n", cfg.synthesis.rpi_variant.c_str());
  for (const GainDesign& gi : d.gains) {
    if (!gi.available) {
      std::printf("  %-11s not available: %s\n", gi.name.c_str(), gi.message.c_str());
      continue;
    }
    double worst = 0.0;
    for (double r : gi.vertex_spectral_radius) worst = std::max(worst, r);
    std::printf("  %-11s spectral radius %.6f (worst vertex %.6f), j = %d, margin %.3f%s%s\n", gi.name.c_str(),
                gi.vertex_spectral_radius.front(), worst, gi.j, gi.margin, gi.tube_ok ? "" : ", tube: ",
                gi.tube_ok ? "" : gi.tube_message.c_str());
  }
  std::printf("selected: %s; RPI j = %d, alpha = %.4f, %d generators, invariance (support, %d directions): worst "
              "ratio %.6f\n",
              g.name.c_str(), d.tube.j, d.tube.alpha, d.tube.Z.order(), d.support_check.directions,
              d.support_check.worst_ratio);
  std::printf("tightened sets non-empty; robustness margin %.3f (W may grow by this factor)\n", d.margin);
  std::printf("set sizes (1-norm radius / volume of the interval hulls):\n");
  for (const VariantComparison& v : d.variants) {
    if (!v.ok) {
      std::printf("  %-10s %s\n", v.variant.c_str(), v.message.c_str());
      continue;
    }
    std::printf("  %-10s Z %.4g / %.3g   X_bar %.4g / %.3g   U_bar %.4g / %.3g   support ratio %.4f %s\n",
                v.variant.c_str(), v.z.one_norm_radius, v.z.volume, v.x_bar.one_norm_radius, v.x_bar.volume,
                v.u_bar.one_norm_radius, v.u_bar.volume, v.support_ratio, v.message.c_str());
  }
  std::printf("QP: N = %d, M = %d, %d variables, %d constraints\n", d.qp.N, d.qp.M, d.qp.variables(),
              d.qp.variables() + d.qp.state_constraints());
  if (cfg.model == ModelKind::Tiltrotor) {
    const EnvelopeSettings& e = d.envelope;
    std::printf("envelope: acceleration [%.3g, %.3g] x [%.3g, %.3g] x [%.3g, %.3g] m/s^2, speed <= %.3g m/s, %s; "
                "feedforward f_r in [%.3f, %.3f] N\n",
                e.acceleration_min(0), e.acceleration_max(0), e.acceleration_min(1), e.acceleration_max(1),
                e.acceleration_min(2), e.acceleration_max(2), e.speed_max, e.yaw_text().c_str(), a.feedforward_min(0),
                a.feedforward_max(0));
  }
  if (cfg.tube_law.offset_free && cfg.model == ModelKind::Tiltrotor) {
    std::printf("tube law: offset-free (observer gain %.3g); the steady state of 1 N on the load takes, per axis,\n",
                cfg.tube_law.observer_gain);
    for (int j = 0; j < 3; ++j) {
      const Eigen::VectorXd us = target.Tu.col(j).cwiseQuotient(a.N_u);
      const Eigen::VectorXd xs = target.Tx.col(j).cwiseQuotient(a.N_x);
      std::printf("  %c: u_s = (%.3f, %.3f) N, (%.4f, %.4f) N m; load phi %.3f, theta %.3f, gamma (%.3f, %.3f) rad\n",
                  "xyz"[j], us(0), us(1), us(2), us(3), xs(3), xs(4), xs(6), xs(7));
    }
  } else if (cfg.tube_law.offset_free) {
    std::printf("tube law: offset-free (observer gain %.3g)\n", cfg.tube_law.observer_gain);
  } else {
    std::printf("tube law: Mayne's (the thesis')\n");
  }
  if (d.kalman) {
    std::printf("estimation: Kalman filter on %zu measured rows, %ld residual channels, error spectral radius %.6f\n",
                d.kf.measured_rows.size(), static_cast<long>(d.kf.E_c.cols()), d.kf.spectral_radius);
    std::printf("  noise through the tube gain (input std from the estimation error; input weights x scale):\n");
    for (const auto& t : d.noise_tradeoff) {
      std::printf("    x %-6g", t.scale);
      for (int i = 0; i < a.m; ++i) std::printf(" %s %.3g", a.input_names[static_cast<std::size_t>(i)].c_str(), t.input_noise_std(i));
      std::printf("; spectral radius %.6f, robustness margin %.3f\n", t.spectral_radius, t.margin);
    }
  }
  if (d.kalman && !d.of_computed) {
    std::printf("output-feedback tube (Mayne et al. 2006): not computed (not applied): %s\n", d.of_message.c_str());
  }
  if (d.of_computed) {
    std::printf("output-feedback tube (Mayne et al. 2006): the sets hold up to %.4g times the configured noise box "
                "(bounded noise), %.4g times its standard deviations (Gaussian noise, chance constraints at %g sigma)%s\n",
                d.of.noise_margin, d.of.noise_margin_gaussian, d.cfg.estimation.noise_bound_sigmas,
                !d.output_feedback ? "; not applied: estimation.output_feedback_tube is false"
                : d.cfg.estimation.gaussian_noise() ? "; the Gaussian form applied"
                                   : "; the bounded form applied");
  }
  if (a.soft_constraints) {
    std::printf("soft state constraints: penalty %.4g%s\n", a.soft_penalty,
                soft.samples > 0 ? (" (" + std::to_string(soft.samples) + " sampled QPs, largest multiplier sum " +
                                    std::to_string(soft.largest_multiplier_sum) + ")").c_str()
                                 : " (configured)");
  }
  std::printf("artifact: %s\n", o.out.c_str());
  if (!o.report.empty()) std::printf("report: %s\n", o.report.c_str());
}

void run_inspect(const std::string& file, bool json) {
  const ControllerArtifact a = load_artifact(file);
  if (json) {
    nlohmann::json j = {{"format_version", kArtifactVersion}, {"model", a.model == ModelKind::Tiltrotor ? "tiltrotor" : "linear"},
                        {"n", a.n}, {"m", a.m}, {"N", a.N}, {"M", a.M}, {"measured", a.measured},
                        {"state_names", a.state_names}, {"input_names", a.input_names},
                        {"sample_time", a.sample_time}, {"tube_gain", a.tube_gain}, {"rpi_variant", a.rpi_variant},
                        {"terminal_cost", a.terminal_cost}, {"vertices", a.A_vertices.size()},
                        {"z_generators", a.Z.order()}, {"robustness_margin", a.margin},
                        {"input_rate_weights", input_rate_weights(a)}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("%s: tmpc controller artifact, format version %u\n", file.c_str(), kArtifactVersion);
  std::printf("  model %s: %d states (%d measured), %d inputs, T = %.4g s, horizons N = %d, M = %d\n",
              a.model == ModelKind::Tiltrotor ? "tiltrotor" : "linear", a.n, a.measured, a.m, a.sample_time, a.N, a.M);
  if (a.model == ModelKind::Tiltrotor) {
    const EnvelopeSettings& e = a.envelope;
    std::printf("  envelope: acceleration [%.3g, %.3g] x [%.3g, %.3g] x [%.3g, %.3g] m/s^2, speed <= %.3g m/s, %s\n",
                e.acceleration_min(0), e.acceleration_max(0), e.acceleration_min(1), e.acceleration_max(1),
                e.acceleration_min(2), e.acceleration_max(2), e.speed_max, e.yaw_text().c_str());
  }
  std::printf("  tube gain %s, RPI %s (%d generators), terminal cost %s, %zu LPV vertices\n", a.tube_gain.c_str(),
              a.rpi_variant.c_str(), a.Z.order(), a.terminal_cost.c_str(), a.A_vertices.size());
  std::printf("  robustness margin %.3f\n", a.margin);
  if (a.rate_weighted()) {
    std::printf("  input-rate weights (weights.input_rate, physical):");
    for (double w : input_rate_weights(a)) std::printf(" %.4g", w);
    std::printf("\n");
  }
  std::printf("  tightened input set (physical, error coordinates):\n");
  for (int i = 0; i < a.m; ++i) {
    std::printf("    %-6s [%.4f, %.4f] of [%.4f, %.4f]\n", a.input_names[static_cast<std::size_t>(i)].c_str(), a.u_bar.lo(i) / a.N_u(i),
                a.u_bar.hi(i) / a.N_u(i), a.U.lo(i) / a.N_u(i), a.U.hi(i) / a.N_u(i));
  }
  std::printf("  tightened state set: half-width kept per state (physical):\n");
  for (int i = 0; i < a.n; ++i) {
    std::printf("    %-12s +-%.4g of +-%.4g\n", a.state_names[static_cast<std::size_t>(i)].c_str(), a.x_bar.hi(i) / a.N_x(i), a.X.hi(i) / a.N_x(i));
  }
}

struct ExportOptions {
  std::string controller;
  std::string x0;
  std::string out;
};

}  // namespace

Eigen::VectorXd parse_vector(const std::string& s, int n, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (item.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::runtime_error(what + ": '" + item + "' is not a number");
    }
  }
  if (static_cast<int>(v.size()) != n) {
    throw std::runtime_error(what + ": expected " + std::to_string(n) + " comma-separated values, got " + std::to_string(v.size()));
  }
  Eigen::VectorXd out(n);
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[static_cast<std::size_t>(i)])) throw std::runtime_error(what + ": value " + std::to_string(i) + " is not finite");
    out(i) = v[static_cast<std::size_t>(i)];
  }
  return out;
}

namespace {

void run_export(const ExportOptions& o) {
  const ControllerArtifact a = load_artifact(o.controller);
  const Eigen::VectorXd x0 = parse_vector(o.x0, a.n, "--x0");
  const MpcQpData d = a.qp();
  const CondensedQp qp = condensed_qp(d, x0);
  auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  std::vector<std::string> vars;
  for (int k = 0; k < a.M; ++k) {
    for (int i = 0; i < a.m; ++i) vars.push_back(std::string("u_bar[") + std::to_string(k) + "]." + a.input_names[static_cast<std::size_t>(i)]);
  }
  nlohmann::json j = {
      {"form", "minimize 1/2 z'Hz + f'z subject to lo <= A z <= hi (normalized coordinates)"},
      {"controller", o.controller},
      {"x0", vec(x0)},
      {"variables", vars},
      {"H", json_rows(qp.H)},
      {"f", vec(qp.f)},
      {"A", json_rows(qp.A)},
      {"lo", vec(qp.lo)},
      {"hi", vec(qp.hi)},
      {"constant", qp.constant},
      {"N_u", vec(a.N_u)},
  };
  std::ofstream out(o.out);
  if (!out) throw std::runtime_error(o.out + ": cannot write");
  out << j.dump() << "\n";
  std::printf("QP with %zu variables and %ld constraint rows written to %s\n", vars.size(), static_cast<long>(qp.A.rows()),
              o.out.c_str());
}

}  // namespace

void register_design(CLI::App& app) {
  auto d = std::make_shared<DesignOptions>();
  CLI::App* sub = app.add_subcommand("design", "Offline tube synthesis: gain, RPI set, tightened sets, QP data");
  sub->add_option("--config", d->config, "design configuration (YAML)")->check(CLI::ExistingFile);
  sub->add_option("--out", d->out, "controller artifact to write")->required();
  sub->add_option("--report", d->report, "JSON report to write");
  sub->add_flag("--explicit", d->explicit_law, "also build the explicit MPC law (config section `explicit`) into OUT + 'x'");
  sub->callback([d]() { run_design(*d); });

  auto file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  CLI::App* ins = app.add_subcommand("inspect", "Print what a controller artifact holds");
  ins->add_option("file", *file, "controller artifact")->required();
  ins->add_flag("--json", *json, "print JSON");
  ins->callback([file, json]() { run_inspect(*file, *json); });

  auto e = std::make_shared<ExportOptions>();
  CLI::App* ex = app.add_subcommand("export-qp", "Write the nominal QP for one state as solver-neutral JSON");
  ex->add_option("--controller", e->controller, "controller artifact")->required();
  ex->add_option("--x0", e->x0, "normalized nominal state, n comma-separated values")->required();
  ex->add_option("--out", e->out, "JSON file to write")->required();
  ex->callback([e]() { run_export(*e); });
}

}  // namespace tmpc::cli
