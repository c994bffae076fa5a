// The synthesis pipeline on the case study: non-empty tightened sets with a clear
// margin, the report's keys, and clear errors for impossible designs.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "design_fixture.hpp"

namespace tmpc {
namespace {

TEST(Design, CaseStudyTightenedSetsAreNonEmptyWithAClearMargin) {
  const ControllerDesign& d = test::quick_design();
  EXPECT_FALSE(d.x_bar.empty());
  EXPECT_FALSE(d.u_bar.empty());
  EXPECT_GT(d.margin, 2.0);  // W may grow at least twofold before a set empties
  // Tightened sets lie inside the constraint sets and shrink by the tube's hull.
  EXPECT_TRUE(((d.x_bar.hi - d.X.hi).array() <= 0).all());
  EXPECT_TRUE(((d.u_bar.lo - d.U.lo).array() >= 0).all());
  const Eigen::VectorXd r = d.tube.Z.radius();
  EXPECT_LT((d.X.hi - d.x_bar.hi - r - d.tube.Z.c).cwiseAbs().maxCoeff(), 1e-12);
  // Input bounds in error coordinates hold along the whole reference.
  EXPECT_LT(d.U.lo(0) / d.em.N_u(0), -11.0);
  EXPECT_GT(d.U.hi(0) / d.em.N_u(0), 18.0);
  EXPECT_EQ(d.qp.variables(), d.cfg.synthesis.control_horizon * 4);
}

TEST(Design, ReportHoldsTheRequiredFigures) {
  const ControllerDesign& d = test::quick_design();
  const nlohmann::json j = nlohmann::json::parse(design_report_json(d));
  for (const char* key : {"K", "spectral_radius", "rpi", "set_sizes", "tightened", "robustness_margin", "uncertainty", "gains"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["K"].size(), 4u);
  EXPECT_EQ(j["spectral_radius"]["vertices"].size(), 8u);
  EXPECT_GT(j["rpi"]["j"].get<int>(), 0);
  EXPECT_EQ(j["set_sizes"].size(), 3u);
  EXPECT_EQ(j["tightened"]["x_bar"]["hi_physical"].size(), 24u);
}

TEST(Design, EmptyTightenedSetIsAnErrorNamingTheDimension) {
  Config c = test::quick_config();
  c.synthesis.w_state_fraction.setConstant(0.01);  // far beyond the margin
  try {
    design_controller(c, "");
    FAIL() << "a design with an empty tightened set was accepted";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("empty in dimension"), std::string::npos) << msg;
    EXPECT_NE(msg.find("synthesis.uncertainty"), std::string::npos) << msg;  // the section it came from
  }
}

TEST(Design, NumericalFailuresNameTheConfigSectionTheyCameFrom) {
  Config c = test::quick_config();
  c.source = "fast.yaml";
  c.envelope.trajectories.clear();
  c.envelope.acceleration_max = Eigen::Vector3d(2000.0, 0.2, 0.15);  // no trim exists at 2,000 m/s^2
  try {
    design_controller(c, "");
    FAIL() << "a design without a trim was accepted";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("fast.yaml: envelope"), std::string::npos) << msg;
    EXPECT_NE(msg.find("trim"), std::string::npos) << msg;
  }
}

/// The second system with a Kalman filter (the output-feedback tube's tests): the
/// force's process noise `force` sets how fast the filter's force estimate moves.
Config mass_spring_with_filter(double force) {
  const std::string path = test::source_dir() + "/config/mass_spring.yaml";
  Config c = load_config_from_string(read_config_file(path, "configuration"), path);
  EstimationSettings& e = c.estimation;
  e.observer = "kalman";
  e.noise = {0.001, 0.001, 0.01, 0.01};  // position, angle, velocity, angular rate
  e.process_force = force;
  e.process_residual = 1e-9;
  return c;
}

TEST(Design, TheGaussianOutputFeedbackTubeTightensByTheNoisesStandardDeviations) {
  Config c = mass_spring_with_filter(0.02);
  const ControllerDesign plain = design_controller(c, "");
  ASSERT_TRUE(plain.of_computed) << plain.of_message;
  EXPECT_FALSE(plain.output_feedback);
  c.estimation.output_feedback_tube = true;
  c.estimation.output_feedback_noise = "gaussian";
  const ControllerDesign d = design_controller(c, "");
  ASSERT_TRUE(d.output_feedback);
  // X_bar = X - (Z_W + E_W,x + z sigma_x), each state's half-width, written out here.
  const OutputFeedbackTube& t = d.of;
  for (Eigen::Index i = 0; i < d.X.dim(); ++i) {
    const double expected = d.X.half_width()(i) - t.Z_W.radius()(i) - (i < d.kf.p ? t.E_W.radius()(i) : 0.0) - t.x_sigmas_v(i);
    EXPECT_NEAR(d.x_bar.half_width()(i), expected, 1e-12) << i;
  }
  EXPECT_LT(d.x_bar.half_width()(0), plain.x_bar.half_width()(0));
  EXPECT_GT(t.noise_margin_gaussian, 1.0);
  const ControllerArtifact a = make_artifact(d);
  EXPECT_EQ(a.noise_margin, t.noise_margin_gaussian);
  EXPECT_GT(a.estimation_error_radius(0), 0.0);
}

TEST(Design, AnOutputFeedbackTubeThatCannotBeComputedIsReportedUnlessApplied) {
  // A force estimate that hardly moves: the estimation loop's spectral radius within
  // 1e-6 of 1, too slow for the RPI series.
  Config c = mass_spring_with_filter(1e-9);
  const ControllerDesign d = design_controller(c, "");
  EXPECT_FALSE(d.of_computed);
  EXPECT_NE(d.of_message.find("estimation.output_feedback_tube"), std::string::npos) << d.of_message;
  const nlohmann::json j = nlohmann::json::parse(design_report_json(d));
  EXPECT_FALSE(j["estimation"]["output_feedback_tube"]["computed"].get<bool>());
  EXPECT_TRUE(j["estimation"]["noise_monitor"].is_null());  // no switched observer configured
  c.estimation.monitor_residual_below = 0.02;
  c.estimation.monitor_filter_above = 0.04;
  const nlohmann::json k = nlohmann::json::parse(design_report_json(design_controller(c, "")));
  EXPECT_EQ(k["estimation"]["noise_monitor"]["residual_below"].get<double>(), 0.02);
  EXPECT_EQ(k["estimation"]["noise_monitor"]["filter_above"].get<double>(), 0.04);
  EXPECT_EQ(k["estimation"]["noise_monitor"]["window_s"].get<double>(), 1.0);
  c.estimation.output_feedback_tube = true;
  try {
    design_controller(c, "");
    FAIL() << "an output-feedback tube that could not be computed was applied";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("estimation.output_feedback_tube"), std::string::npos) << e.what();
  }
}

TEST(Design, SampledUncertaintyIsReportedAsSuch) {
  Config c = test::quick_config();
  c.synthesis.w_source = "sampled";
  c.synthesis.w_samples = 40;
  c.synthesis.w_sample_box = 0.01;
  c.synthesis.w_sample_fraction = 0.10;
  const ControllerDesign d = design_controller(c, "");
  EXPECT_NE(d.w_description.find("sampled"), std::string::npos);
  // The sampled box contains the configured floor and exceeds it somewhere.
  EXPECT_TRUE(((d.W.radius() - c.synthesis.w_state_fraction).array() >= -1e-15).all());
  EXPECT_GT(d.W.radius().maxCoeff(), 10.0 * c.synthesis.w_state_fraction.maxCoeff());
  EXPECT_GT(d.margin, 1.0);
}

}  // namespace
}  // namespace tmpc
