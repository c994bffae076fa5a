// Short scenario checks (seconds, not the 80 s missions: outside the label `slow`): a
// trajectory outside the envelope is refused before take-off, a start offset is where
// the plant starts, and the second system (a mass-spring pair) is designed and flown by
// the same code.
#include <gtest/gtest.h>

#include "fly_scenario.hpp"

namespace tmpc {
namespace {

using test::artifact;
using test::fly;

TEST(Scenarios, AMissionOutsideTheEnvelopeIsRefusedBeforeTakeOff) {
  Scenario s = test::shipped_scenario("figure_eight");
  s.trajectory = make_figure_eight({Eigen::Vector3d(0, 0, 3), Eigen::Vector2d(8, 3), 0.11, 0.0});  // a_x up to 0.097 m/s^2
  try {
    run_mission(artifact(), s, MissionOptions{});
    FAIL() << "an out-of-envelope mission flew";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("scenario figure_eight: refused before take-off"), std::string::npos) << msg;
    EXPECT_NE(msg.find("outside the envelope [-0.06, 0.06]"), std::string::npos) << msg;
  }
}

TEST(Scenarios, AStartOffsetIsWhereThePlantStarts) {
  Scenario s = test::quiet_helix();
  s.start_position_offset = Eigen::Vector3d(0.1, -0.05, 0.0);
  MissionOptions o;
  o.duration = 6.0;
  const MissionMetrics m = run_mission(artifact(), s, o);
  EXPECT_NEAR(m.max_abs_error[0], 0.1, 1e-3);  // the largest error is about the first one
  EXPECT_NEAR(m.max_abs_error[1], 0.05, 1e-3);
  EXPECT_EQ(m.state_constraint_violations, 0);
  EXPECT_EQ(m.fallback_periods, 0);
  // The shipped switched observer starts on the Kalman filter; the x offset is 20 of
  // its noise's sigmas from the prior (on the reference), so x starts at the
  // measurement (through the gain from the prior, the true error was outside the tube
  // around that estimate in 5 of the first check's 7 periods), and the reference joins
  // from the vehicle: no exit at all, as with the residual observer alone.
  EXPECT_EQ(m.filtered_periods, 7);
  EXPECT_EQ(m.tube_exits, 0);
  o.estimator.observer = "residual";
  EXPECT_EQ(run_mission(artifact(), s, o).tube_exits, 0);
}

// README "A second system": designed from config/mass_spring.yaml and flown by the
// same mission code (the runtime loop flies it in test_controller_loop).
TEST(Scenarios, TheSecondSystemIsDesignedAndFlown) {
  const ControllerArtifact& a = test::mass_spring_artifact();
  EXPECT_EQ(a.model, ModelKind::Linear);
  EXPECT_EQ(a.state_names, (std::vector<std::string>{"p1", "p2", "v1", "v2", "int_p1", "int_p2"}));
  EXPECT_EQ(a.input_names, (std::vector<std::string>{"u1", "u2"}));
  EXPECT_GT(a.margin, 1.0);
  const MissionMetrics m = fly("mass_spring_steps", a);
  EXPECT_EQ(m.periods, 750);
  EXPECT_FALSE(m.diverged);
  EXPECT_EQ(m.state_constraint_violations, 0);
  EXPECT_EQ(m.fallback_periods, 0);
  EXPECT_NEAR(m.max_abs_error[0], 0.3, 1e-9);  // the start offset
  EXPECT_NEAR(m.rmse[0], 0.0415, 0.02 * 0.0415);
  EXPECT_NEAR(m.rmse[1], 0.0062, 0.02 * 0.0062);
  ASSERT_EQ(m.d_hat_final.size(), 2u);  // the observer's estimate of the two forces: 1 N and 0.5 N
  EXPECT_NEAR(m.d_hat_final[0], 1.0, 0.02);
  EXPECT_NEAR(m.d_hat_final[1], 0.5, 0.02);
  // A tiltrotor scenario does not fit a linear model.
  EXPECT_THROW(run_mission(a, test::shipped_scenario("figure_eight"), MissionOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
