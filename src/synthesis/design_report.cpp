// JSON report of a design (stable keys; matrices as lists of rows).
#include <nlohmann/json.hpp>

#include "tmpc/synthesis/design.hpp"
#include "tmpc/synthesis/json_rows.hpp"

namespace tmpc {

namespace {

nlohmann::json vec(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }
nlohmann::json size(const SetSize& s) { return {{"one_norm_radius", s.one_norm_radius}, {"volume", s.volume}}; }
/// A normalized box, with its physical equivalent (divided by the scaling).
nlohmann::json box(const Box& b, const Eigen::VectorXd& scale) {
  return {{"lo", vec(b.lo)},
          {"hi", vec(b.hi)},
          {"lo_physical", vec(b.lo.cwiseQuotient(scale))},
          {"hi_physical", vec(b.hi.cwiseQuotient(scale))}};
}

}  // namespace

std::string design_report_json(const ControllerDesign& d) {
  nlohmann::json j;
  const SynthesisSettings& s = d.cfg.synthesis;
  j["config"] = d.cfg.source;
  j["coordinates"] = "normalized: x_n = N_x x, u_n = N_u u (physical values given as *_physical)";
  j["model"] = d.cfg.model == ModelKind::Tiltrotor ? "tiltrotor" : "linear";
  j["state_names"] = d.state_names;
  j["input_names"] = d.input_names;
  j["envelope"] = {{"acceleration_min", vec(d.envelope.acceleration_min)},
                   {"acceleration_max", vec(d.envelope.acceleration_max)},
                   {"speed_max", d.envelope.speed_max},
                   {"yaw", d.envelope.yaw},
                   {"yaw_tolerance", d.envelope.yaw_tolerance},
                   {"yaw_rate_max", d.envelope.yaw_rate_max},  // < 0: the fixed yaw
                   {"feedforward_min", vec(d.em.u_r_min)},
                   {"feedforward_max", vec(d.em.u_r_max)}};
  j["time_s"] = {{"error_model", d.seconds.error_model}, {"uncertainty", d.seconds.uncertainty},
                 {"gains", d.seconds.gains},             {"rpi_and_margins", d.seconds.rpi},
                 {"checks", d.seconds.checks},           {"qp", d.seconds.qp},
                 {"total", d.seconds.total}};
  j["error_model"] = {{"discretization", d.em.discretization == Discretization::Zoh ? "zoh" : "euler"},
                      {"sample_time", d.em.sample_time},
                      {"lpv_vertices", d.em.A_vertices.size()},
                      {"affinity_residual", d.em.lpv.affinity_residual},
                      {"N_x", vec(d.em.N_x)},
                      {"N_u", vec(d.em.N_u)}};
  j["uncertainty"] = {{"description", d.w_description},
                      {"generators", d.W.order()},
                      {"half_widths", vec(d.W.radius())},
                      {"half_widths_physical", vec(d.W.radius().cwiseQuotient(d.em.N_x))}};
  nlohmann::json gains = nlohmann::json::array();
  for (const GainDesign& g : d.gains) {
    nlohmann::json gj = {{"name", g.name}, {"available", g.available}, {"message", g.message}, {"seconds", g.seconds}};
    if (g.available) {
      gj["K"] = json_rows(g.K);
      gj["spectral_radius"] = {{"nominal", g.vertex_spectral_radius.front()},
                               {"vertices", std::vector<double>(g.vertex_spectral_radius.begin() + 1, g.vertex_spectral_radius.end())}};
      gj["tube"] = {{"ok", g.tube_ok},
                    {"message", g.tube_message},
                    {"j", g.j},
                    {"alpha", g.alpha},
                    {"generators", g.generators},
                    {"z_hull_over_box", g.tube_ok || g.generators > 0 ? vec(g.z_hull.half_width()) : nlohmann::json()},
                    {"robustness_margin", g.margin}};
    }
    if (g.name != "lqr") {
      gj["lmi"] = {{"status", to_string(g.lmi.status)},
                   {"lambda", g.lmi.lambda},
                   {"kappa", g.lmi.kappa},
                   {"solver_seconds", g.lmi.seconds},
                   {"variables", g.lmi.variables},
                   {"worst_block_eigenvalue", g.lmi.worst_block_eigenvalue},
                   {"input_bound_ratio", g.lmi.input_bound_ratio},
                   {"zeta_norm", g.lmi.zeta.size() > 0 ? g.lmi.zeta.norm() : 0.0},
                   {"certified_w_scale", g.certified_w_scale},
                   {"refuted_w_scale", g.refuted_w_scale}};
    }
    gains.push_back(gj);
  }
  j["gains"] = gains;
  const GainDesign& sel = d.gains[static_cast<std::size_t>(d.selected)];
  j["selected_gain"] = sel.name;
  j["K"] = json_rows(d.K);
  j["K_lqr"] = json_rows(d.K_lqr);
  j["spectral_radius"] = {{"nominal", sel.vertex_spectral_radius.front()},
                          {"vertices", std::vector<double>(sel.vertex_spectral_radius.begin() + 1, sel.vertex_spectral_radius.end())}};
  j["rpi"] = {{"variant", s.rpi_variant},
              {"lambda", s.rpi_lambda},
              {"j", d.tube.j},
              {"alpha", d.tube.alpha},
              {"generators", d.tube.Z.order()},
              {"lpv_iterations", d.tube.lpv_iterations},
              {"w_box_hull", d.tube.w_box_hull},
              {"support_check", {{"worst_ratio", d.support_check.worst_ratio},
                                 {"worst_vertex", d.support_check.worst_vertex},
                                 {"directions", d.support_check.directions}}}};
  nlohmann::json variants = nlohmann::json::array();
  for (const VariantComparison& v : d.variants) {
    variants.push_back({{"variant", v.variant}, {"ok", v.ok}, {"message", v.message}, {"j", v.j}, {"alpha", v.alpha},
                        {"z", size(v.z)}, {"x_bar", size(v.x_bar)}, {"u_bar", size(v.u_bar)},
                        {"support_ratio", v.support_ratio}});
  }
  j["set_sizes"] = variants;
  j["tightened"] = {{"x_bar", box(d.x_bar, d.em.N_x)}, {"u_bar", box(d.u_bar, d.em.N_u)}};
  j["robustness_margin"] = {{"scale", d.margin}, {"method", d.margin_method}};
  j["terminal_cost"] = s.terminal_cost;
  if (d.kalman) {
    const Eigen::MatrixXd post = (Eigen::MatrixXd::Identity(d.kf.P.rows(), d.kf.P.cols()) - d.kf.L * d.kf.C) * d.kf.P;
    Eigen::VectorXd sd = post.diagonal().cwiseSqrt();
    for (int i = 0; i < d.kf.p; ++i) sd(i) /= d.em.N_x(i);  // physical units (the disturbances are already)
    nlohmann::json trade = nlohmann::json::array();
    for (const auto& t : d.noise_tradeoff) {
      trade.push_back({{"input_weight_scale", t.scale}, {"input_noise_std", vec(t.input_noise_std)},
                       {"spectral_radius", t.spectral_radius}, {"robustness_margin", t.margin}});
    }
    j["estimation"] = {{"observer", "kalman"},
                       {"measured_rows", d.kf.measured_rows},
                       {"residual_channels", d.kf.E_c.cols()},
                       {"error_spectral_radius", d.kf.spectral_radius},
                       {"estimation_error_std", vec(sd)},
                       {"noise_tradeoff", trade},
                       {"output_feedback_tube", {{"applied", d.output_feedback},
                                                 {"computed", d.of_computed},
                                                 {"not_computed_because", d.of_message},
                                                 {"noise", d.cfg.estimation.output_feedback_noise},
                                                 {"noise_margin", d.of_computed ? d.of.noise_margin : 0.0},
                                                 {"estimation_error_half_widths", d.of_computed ? vec(d.of.e_x_radius.cwiseQuotient(d.em.N_x)) : nlohmann::json()},
                                                 {"control_tube_half_widths", d.of_computed ? vec(d.of.Z_c.radius().cwiseQuotient(d.em.N_x)) : nlohmann::json()},
                                                 {"j_estimation", d.of.j_estimation},
                                                 {"gaussian", d.of_computed ? nlohmann::json{
                                                     {"noise_margin", d.of.noise_margin_gaussian},
                                                     {"estimation_error_half_widths", vec(d.of.e_x_radius_gaussian.cwiseQuotient(d.em.N_x))},
                                                     {"state_error_half_widths", vec(d.of.x_sigmas_v.cwiseQuotient(d.em.N_x))},
                                                     {"input_error_half_widths", vec(d.of.u_sigmas_v.cwiseQuotient(d.em.N_u))}}
                                                                            : nlohmann::json()}}}};
    const EstimationSettings& e = d.cfg.estimation;
    // The filter's start (estimator.hpp start_gains()): null without a start prior.
    if (e.start_force > 0.0 || e.start_residual > 0.0 || e.start_state > 0.0) {
      const std::size_t periods =
          start_gains(d.kf, start_covariance(d.kf, d.em.D_n.cols(), e.start_force, e.start_residual, e.start_state)).size();
      j["estimation"]["start_prior"] = {{"force_std", e.start_force}, {"residual_std", e.start_residual},
                                        {"state_noise_multiple", e.start_state}, {"scheduled_periods", periods},
                                        {"scheduled_s", static_cast<double>(periods) * d.em.sample_time}};
    } else {
      j["estimation"]["start_prior"] = nlohmann::json();
    }
    // The switched observer (runtime/noise_monitor.hpp): null without a noise monitor.
    j["estimation"]["noise_monitor"] =
        e.monitor_residual_below > 0.0
            ? nlohmann::json{{"residual_below", e.monitor_residual_below},
                             {"filter_above", e.monitor_filter_above},
                             {"window_s", e.monitor_window_s}}
            : nlohmann::json();
  } else {
    j["estimation"] = {{"observer", "residual"}};
  }
  j["qp"] = {{"N", d.qp.N}, {"M", d.qp.M}, {"variables", d.qp.variables()},
             {"constraints", d.qp.variables() + d.qp.state_constraints()}};
  return j.dump(2);
}

}  // namespace tmpc
