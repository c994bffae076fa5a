// The shipped scenarios flown for their full length with the default artifact (no
// redesign): the figure-eight, the waypoint tour and the planner's CSV track with zero
// state-constraint violations; the gusts, which exceed what the shipped controller
// holds (issue "noise and gusts"), with their violations counted and reported; the
// noisy sensors on its switched observer, and on the residual observer alone. The short scenario checks: test_scenario_checks.cpp.
#include <algorithm>
#include <array>
#include <cstdint>

#include <gtest/gtest.h>

#include "fly_scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/estimator.hpp"

namespace tmpc {
namespace {

using test::fly;

/// A flight beyond the hard constraints kept to the end by the softened MPC: no abort,
/// no LQR period, the violations and softened periods the README states (to 5 %).
void expect_softened_flight(const MissionMetrics& m, double violations, double softened) {
  EXPECT_FALSE(m.diverged);
  EXPECT_EQ(m.fallback_periods, 0);
  EXPECT_NEAR(static_cast<double>(m.state_constraint_violations), violations, 0.05 * violations) << "README states " << violations;
  EXPECT_NEAR(static_cast<double>(m.softened_periods), softened, 0.05 * softened) << "README states " << softened;
}

void expect_rmse(const MissionMetrics& m, double x, double y, double z) {
  EXPECT_NEAR(m.rmse[0], x, 0.02 * x) << "README states " << x;
  EXPECT_NEAR(m.rmse[1], y, 0.02 * y) << "README states " << y;
  EXPECT_NEAR(m.rmse[2], z, 0.02 * z) << "README states " << z;
}

// README "Scenarios" table, first rows: inside the envelope, no redesign.
TEST(Scenarios, FigureEightWaypointsAndTheCsvTrackFlyWithTheDefaultArtifact) {
  const MissionMetrics eight = fly("figure_eight");
  EXPECT_EQ(eight.periods, 6667);
  EXPECT_EQ(eight.state_constraint_violations, 0);
  EXPECT_EQ(eight.fallback_periods, 0);
  expect_rmse(eight, 0.0307, 0.0300, 0.00211);
  EXPECT_EQ(eight.window_starts, (std::vector<double>{0.0, 20.0, 40.0, 60.0}));  // from the scenario's events
  const MissionMetrics tour = fly("waypoints");
  EXPECT_EQ(tour.periods, 6667);
  EXPECT_EQ(tour.state_constraint_violations, 0);
  EXPECT_EQ(tour.fallback_periods, 0);
  expect_rmse(tour, 0.0295, 0.0292, 0.000677);
  EXPECT_EQ(tour.window_starts, (std::vector<double>{0.0, 10.0, 40.0}));
  const MissionMetrics track = fly("lissajous_csv");
  EXPECT_EQ(track.periods, 5000);
  EXPECT_EQ(track.state_constraint_violations, 0);
  EXPECT_EQ(track.fallback_periods, 0);
  expect_rmse(track, 0.0341, 0.000233, 0.000571);
}

// README "Scenarios" table, last rows: beyond the shipped design, reported.
TEST(Scenarios, GustsAndNoisySensorsAreFlownAndTheirViolationsReported) {
  const MissionMetrics gusts = fly("gusts");
  EXPECT_EQ(gusts.periods, 6667);
  expect_rmse(gusts, 0.0952, 0.0918, 0.0068);
  // The load's tilt past its box, from the gust's physics (README "Noisy sensors"), and
  // no servo rate past its bound: the law takes the softened optimum near the hard QP's
  // feasibility boundary, where the hard solution's servo rates peaked at 2.82 times
  // their bound (4.70 with the tube gain of lambda's input weights; 9.35 with that gain
  // when the recovery went back to the hard QP as soon as it was feasible).
  EXPECT_NEAR(gusts.violation_max_ratio, 1.22, 0.05 * 1.22);
  EXPECT_EQ(gusts.violation_worst_state, "phi");
  for (const char* servo_rate : {"d_alpha_l", "d_alpha_r"}) {
    const std::size_t servo = static_cast<std::size_t>(
        std::find(gusts.box_names.begin(), gusts.box_names.end(), servo_rate) - gusts.box_names.begin());
    ASSERT_LT(servo, gusts.box_peak_ratio.size());
    EXPECT_LT(gusts.box_peak_ratio[servo], 0.95) << servo_rate;  // 0.92
  }
  // No LQR takeover (1048 periods before soft constraints were shipped): the infeasible
  // QPs, and the two a numerical failure ended, are flown softened; no solve cycles
  // (a softened QP took 4000 steps when its slack curvature was 1e-8, parametric_qp.hpp).
  std::printf("gusts: softened %ld, largest iteration count %d\n", gusts.softened_periods, gusts.iterations_max);
  expect_softened_flight(gusts, 763.0, 991.0);
  EXPECT_LT(gusts.iterations_max, 200);
  // The monitor reads up to 0.0023 of the design noise on the hard law's periods (0.051
  // near 67 s when it read the softened ones too and the hard solution flew up to the
  // feasibility boundary: the filter flew there 1.5 s), far below filter_above.
  std::printf("gusts: filter %ld periods, level max %.4f\n", gusts.filtered_periods, gusts.noise_level_max);
  EXPECT_EQ(gusts.filtered_periods, 7);
  EXPECT_LT(gusts.noise_level_max, 0.005);
  // A sustained 3 N from 10 s (every QP infeasible): the softened MPC flies to the end
  // (the LQR fallback for 5830 periods before soft constraints were shipped).
  // The noise monitor skips the softened periods (tube_controller.hpp) and reads at most
  // 0.0013 of the design noise: the residual observer flies it after the first check.
  // (Reading them too, the smooth swing read 0.046 by the statistic dr (dr - dr_prev) and
  // 0.09 by dr^2, which brought the filter for 4.4 s and let the vertical speed out to
  // 6.65 times its bound.)
  const MissionMetrics held = fly("sustained_force");
  std::printf("sustained_force: worst %s %.3f, filter %ld periods, level max %.4f\n", held.violation_worst_state.c_str(),
              held.violation_max_ratio, held.filtered_periods, held.noise_level_max);
  expect_softened_flight(held, 5766.0, 5814.0);
  EXPECT_NEAR(held.violation_max_ratio, 3.24, 0.05 * 3.24);
  EXPECT_EQ(held.violation_worst_state, "d_x");
  EXPECT_EQ(held.filtered_periods, 7);
  EXPECT_EQ(held.observer_switches, 1);
  EXPECT_LT(held.noise_level_max, 0.0015);  // filter_above: 0.05
  // The residual observer alone (the shipped design's before its switched observer) is
  // the raw measurement through the tube gain: the servo rates chatter past their bound
  // in most periods (up to 4.1 times it), past 4 times it in a few, where the reversion
  // (tube_law.revert_beyond) flies the tube gain's law: 7 periods, no other fallback;
  // the flight goes on to the end (with the tube gain of lambda's input weights the
  // servo rates ran away: aborted after 5826 periods, 5310 violations). The shipped
  // design flies these sensors on the filter without a violation
  // (TheSwitchedObserverFlies... below).
  const MissionMetrics noisy = test::fly_residual_observer("noisy_sensors");
  EXPECT_TRUE(noisy.noisy);
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.periods, 6667);
  EXPECT_NEAR(static_cast<double>(noisy.state_constraint_violations), 4959.0, 0.05 * 4959.0);
  EXPECT_NEAR(noisy.violation_max_ratio, 4.14, 0.05 * 4.14);
  expect_rmse(noisy, 0.0355, 0.0309, 0.00317);
  EXPECT_EQ(noisy.fallback_periods, noisy.reverted_periods);
  EXPECT_NEAR(static_cast<double>(noisy.reverted_periods), 7.0, 5.0);
}


// README "Noisy sensors, gusts and soft constraints": the noisy-sensor design
// (config/tiltrotor_noisy.yaml: Kalman filter, softer tube gain, input-rate weights,
// soft constraints).
TEST(Scenarios, TheNoisySensorDesignFliesTheNoiseAndKeepsTheMpcThroughInfeasibleForces) {
  const ControllerArtifact& a = test::noisy_artifact();
  ASSERT_TRUE(a.rate_weighted());
  const MissionMetrics noisy = fly("noisy_sensors", a);
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.periods, 6667);
  EXPECT_EQ(noisy.estimator, "kalman");
  EXPECT_EQ(noisy.state_constraint_violations, 0);
  EXPECT_EQ(noisy.fallback_periods, 0);
  EXPECT_NEAR(noisy.rmse[0], 0.0348, 0.02 * 0.0348);
  EXPECT_NEAR(noisy.rmse[1], 0.0284, 0.02 * 0.0284);
  EXPECT_NEAR(noisy.rmse[2], 0.0102, 0.02 * 0.0102);
  // The input-rate weight's trade-off: the same design without it (Sigma_delta = 0)
  // passes more of the noise to the inputs (total variation, servo torques 2.47 N m
  // against 1.79, thrusts 118 N against 87) and tracks z slightly better (0.0096 m).
  ControllerArtifact unrated = a;
  unrated.Sigma_delta.setZero();
  const MissionMetrics chatter = fly("noisy_sensors", unrated);
  EXPECT_EQ(chatter.state_constraint_violations, 0);
  std::printf("noisy_sensors total variation: torques %.3f %.3f (%.3f %.3f without the rate weight), thrusts %.1f %.1f "
              "(%.1f %.1f)\n", noisy.tcv[2], noisy.tcv[3], chatter.tcv[2], chatter.tcv[3], noisy.tcv[0], noisy.tcv[1],
              chatter.tcv[0], chatter.tcv[1]);
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT(noisy.tcv[static_cast<std::size_t>(i)], 0.8 * chatter.tcv[static_cast<std::size_t>(i)]) << "input " << i;
  }
  EXPECT_NEAR(chatter.tcv[2], 2.47, 0.05 * 2.47);
  EXPECT_NEAR(noisy.tcv[2], 1.79, 0.05 * 1.79);
  EXPECT_NEAR(chatter.tcv[0], 118.0, 0.05 * 118.0);
  EXPECT_NEAR(noisy.tcv[0], 87.0, 0.05 * 87.0);
  EXPECT_NEAR(chatter.rmse[2], 0.0096, 0.02 * 0.0096);
  // Ten times that weight (100 x lambda): less variation still, z a little worse.
  ControllerArtifact heavier = a;
  heavier.Sigma_delta *= 10.0;
  const MissionMetrics calm = fly("noisy_sensors", heavier);
  EXPECT_EQ(calm.state_constraint_violations, 0);
  EXPECT_NEAR(calm.tcv[2], 1.53, 0.05 * 1.53);
  EXPECT_NEAR(calm.tcv[0], 79.0, 0.05 * 79.0);
  EXPECT_NEAR(calm.rmse[2], 0.0111, 0.02 * 0.0111);
  // Why the shipped design has none: 10 x lambda moves its noise-free z RMSE from
  // 0.0021 to 0.0029 m (the issue allows 10 %).
  ControllerArtifact shipped_rated = test::artifact();
  shipped_rated.Sigma_delta = 10.0 * shipped_rated.Sigma_lambda;
  EXPECT_NEAR(fly("thesis_helix", shipped_rated).rmse[2], 0.0029, 0.02 * 0.0029);
  const MissionMetrics quiet = fly("thesis_helix", a);
  EXPECT_EQ(quiet.state_constraint_violations, 0);
  EXPECT_NEAR(quiet.rmse[0], 0.0285, 0.02 * 0.0285);
  EXPECT_NEAR(quiet.rmse[1], 0.0273, 0.02 * 0.0273);
  EXPECT_NEAR(quiet.rmse[2], 0.0100, 0.02 * 0.0100);
  const MissionMetrics held = fly("sustained_force", a);  // 3 N from 10 s: every QP infeasible
  expect_softened_flight(held, 5814.0, 5811.0);  // no LQR takeover: the softened QP flies
  // d_z, in the step's transient: the step is read in the filter's innovations, which
  // re-opens its residuals (6.7 with the steady gain alone).
  EXPECT_NEAR(held.violation_max_ratio, 5.44, 0.05 * 5.44);
  EXPECT_EQ(held.step_detections, 1);
  const MissionMetrics gusts = fly("gusts", a);
  expect_softened_flight(gusts, 714.0, 979.0);  // (1048 fallbacks with the shipped design before soft constraints)
  std::printf("gusts, noisy-sensor design: worst %s %.3f\n", gusts.violation_worst_state.c_str(), gusts.violation_max_ratio);
  EXPECT_NEAR(gusts.violation_max_ratio, 1.31, 0.05 * 1.31);  // 1.83, a servo rate, before the multiplier check
}

// README "Noisy sensors": the noisy-sensor design is not tuned to one flight: the
// other shipped tracks with the same noise, and the helix with other noise seeds, fly
// without a violation or a fallback.
TEST(Scenarios, TheNoisySensorDesignFliesOtherTracksAndSeedsThroughTheNoise) {
  const ControllerArtifact& a = test::noisy_artifact();
  const NoiseSpec noise = test::shipped_scenario("noisy_sensors").noise;
  struct Track {
    const char* name;
    double x, y, z;  // RMSE, m (README)
  };
  for (const Track& t : {Track{"figure_eight", 0.0347, 0.0283, 0.0102}, Track{"waypoints", 0.0288, 0.0275, 0.0060},
                         Track{"lissajous_csv", 0.0364, 0.0117, 0.0059}}) {
    Scenario s = test::shipped_scenario(t.name);
    s.noise = noise;
    const MissionMetrics m = run_mission(a, s, MissionOptions{});
    std::printf("%s with noise: RMSE %.4f %.4f %.4f, violations %ld\n", t.name, m.rmse[0], m.rmse[1], m.rmse[2],
                m.state_constraint_violations);
    EXPECT_FALSE(m.diverged) << t.name;
    EXPECT_EQ(m.state_constraint_violations, 0) << t.name;
    EXPECT_EQ(m.fallback_periods, 0) << t.name;
    expect_rmse(m, t.x, t.y, t.z);
  }
  const std::array<std::array<double, 2>, 3> seeds = {{{1.0, 0.0115}, {2.0, 0.0104}, {7.0, 0.0117}}};  // seed, z RMSE
  for (const auto& [seed, z] : seeds) {
    Scenario s = test::shipped_scenario("noisy_sensors");
    s.noise.seed = static_cast<std::uint32_t>(seed);
    const MissionMetrics m = run_mission(a, s, MissionOptions{});
    std::printf("noisy_sensors, seed %g: RMSE %.4f %.4f %.4f\n", seed, m.rmse[0], m.rmse[1], m.rmse[2]);
    EXPECT_FALSE(m.diverged) << seed;
    EXPECT_EQ(m.state_constraint_violations, 0) << seed;
    EXPECT_EQ(m.fallback_periods, 0) << seed;
    EXPECT_NEAR(m.rmse[2], z, 0.02 * z) << seed;
  }
}

// README "Noisy sensors", the switched observer (the shipped config/tiltrotor.yaml): one
// controller for clean and noisy sensors. Its noise monitor hands the law to the
// one-step residual observer when its first check (72 ms) reads clean sensors and
// keeps the Kalman filter while they are noisy: the noise-free thesis mission within
// 10 % of the shipped design's RMSE (0.0308, 0.0301, 0.0021 m; issue "noise and
// gusts"), the noisy sensors, a tenth of their noise and the biased sensors without a
// violation. This is the shipped design: the tests above fly it with the scenarios'
// forces, mass errors and the sensor bias.
TEST(Scenarios, TheSwitchedObserverFliesCleanAndNoisySensorsWithOneController) {
  const ControllerArtifact& a = test::quick_artifact();
  ASSERT_TRUE(a.switched_observer());
  const MissionMetrics clean = fly("thesis_helix", a);
  std::printf("switched, thesis_helix: RMSE %.4f %.4f %.5f, filter %ld periods, %ld switches, level max %.4f\n",
              clean.rmse[0], clean.rmse[1], clean.rmse[2], clean.filtered_periods, clean.observer_switches,
              clean.noise_level_max);
  EXPECT_EQ(clean.estimator, "switched");
  EXPECT_EQ(clean.state_constraint_violations, 0);
  EXPECT_EQ(clean.fallback_periods, 0);
  const double shipped[3] = {0.0308, 0.0301, 0.0021};  // the shipped design's (test above, README)
  for (int i = 0; i < 3; ++i) EXPECT_LE(clean.rmse[static_cast<std::size_t>(i)], 1.10 * shipped[i]) << i;
  expect_rmse(clean, 0.0308, 0.0301, 0.0021);
  EXPECT_EQ(clean.filtered_periods, 7);  // the first check: 5 statistics of 6 differences, 8 measurements
  EXPECT_EQ(clean.observer_switches, 1);
  // The force steps: a residual jump of one or two periods, which the median drops
  // (0.0256 without it: a 2 N step would have read twice that, past the 0.05 that
  // brings the filter back), and the load's swing after them, which the statistic's
  // whiteness drops (0.0029 with the residual change's variance).
  EXPECT_NEAR(clean.noise_level_max, 0.00044, 0.1 * 0.00044);

  const MissionMetrics noisy = fly("noisy_sensors", a);
  std::printf("switched, noisy_sensors: RMSE %.4f %.4f %.4f, filter %ld periods\n", noisy.rmse[0], noisy.rmse[1],
              noisy.rmse[2], noisy.filtered_periods);
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.state_constraint_violations, 0);
  EXPECT_EQ(noisy.fallback_periods, 0);
  EXPECT_EQ(noisy.filtered_periods, noisy.periods);
  expect_rmse(noisy, 0.0346, 0.0283, 0.0096);

  Scenario tenth = test::shipped_scenario("noisy_sensors");  // 0.5 mm, 0.03 deg
  for (double& w : tenth.noise.white) w *= 0.1;
  const MissionMetrics quiet = run_mission(a, tenth, MissionOptions{});
  std::printf("switched, a tenth of the noise: violations %ld, filter %ld periods\n", quiet.state_constraint_violations,
              quiet.filtered_periods);
  EXPECT_EQ(quiet.state_constraint_violations, 0);
  EXPECT_EQ(quiet.filtered_periods, quiet.periods);
  MissionOptions residual;
  residual.estimator.observer = "residual";  // the same design with the residual observer alone
  const MissionMetrics raw = run_mission(a, tenth, residual);
  std::printf("residual observer, a tenth of the noise: violations %ld (worst %s %.2f)\n", raw.state_constraint_violations,
              raw.violation_worst_state.c_str(), raw.violation_max_ratio);
  EXPECT_NEAR(static_cast<double>(raw.state_constraint_violations), 33.0, 0.05 * 33.0);  // why the filter stays there

  // The biased sensors and a sustained 3 N force: ASensorBias... and GustsAndNoisySensors...
}

// README "Noisy sensors": without velocity sensors (config/tiltrotor_noisy_no_velocity.yaml:
// positions, angles and rates measured, the Kalman filter estimating the 3 linear
// velocities) the noisy-sensor design flies the noise without a violation.
TEST(Scenarios, WithoutVelocitySensorsTheFilterEstimatesThemAndTheNoiseIsFlown) {
  const ControllerArtifact a = test::quick_shipped_artifact("tiltrotor_noisy_no_velocity", "noisy-no-velocity");
  ASSERT_EQ(a.estimator, "kalman");
  EXPECT_EQ(a.estimator_rows.size(), 17u);  // 20 physical states less the 3 linear velocities
  const MissionMetrics noisy = fly("noisy_sensors", a);
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.state_constraint_violations, 0);
  EXPECT_EQ(noisy.fallback_periods, 0);
  expect_rmse(noisy, 0.0355, 0.0291, 0.0154);
  const MissionMetrics quiet = fly("thesis_helix", a);
  EXPECT_EQ(quiet.state_constraint_violations, 0);
  EXPECT_EQ(quiet.fallback_periods, 0);
  expect_rmse(quiet, 0.0300, 0.0282, 0.0149);
}

// README "Scenarios" (config/scenarios/biased_sensors.yaml): a constant sensor bias (2 cm
// on positions, 0.5 degree on angles) cannot be seen by any law: the controller holds
// the measured state on the reference, so the true error settles at minus the bias.
// The integral rows are judged on the controller's own integrators: the true integral
// of the yaw error grows by 0.0087 rad a second (0.70 rad s after 80 s, past its 0.5
// bound) whatever the law does. The noisy-sensor design flies the bias with the noise.
// The bias is there from the first measurement: the controller starts from a state
// that looks 0.5 degree off, and the model's prediction of that state (a load swinging
// back) is not what the sensors then read; the residual observer takes the difference
// for a force: one period of that start passes a servo rate's bound by 7 % (0.06 s),
// none after it. The shipped switched observer starts on the filter, which reads the
// start smoothly, and hands over at 84 ms: no violation.
TEST(Scenarios, ASensorBiasShiftsTheTrueErrorByTheBias) {
  const Scenario biased = test::shipped_scenario("biased_sensors");
  ASSERT_DOUBLE_EQ(biased.noise.bias[1], 0.0087);
  const MissionMetrics m = fly("biased_sensors");
  EXPECT_FALSE(m.diverged);
  EXPECT_EQ(m.periods, 6667);
  EXPECT_EQ(m.state_constraint_violations, 0);
  EXPECT_EQ(m.observer_switches, 1);  // the hand-over after the first check is bumpless
  const MissionMetrics r = test::fly_residual_observer("biased_sensors");
  EXPECT_EQ(r.state_constraint_violations, 1);
  EXPECT_EQ(r.violation_worst_state, "d_alpha_r");
  EXPECT_NEAR(r.violation_max_ratio, 1.066, 0.01);
  MissionOptions start;  // the residual observer alone; the period at 0.06 s: 5 periods without it, 6 with it
  start.estimator.observer = "residual";
  start.duration = 0.06;
  EXPECT_EQ(run_mission(test::artifact(), biased, start).state_constraint_violations, 0);
  start.duration = 0.072;
  EXPECT_EQ(run_mission(test::artifact(), biased, start).state_constraint_violations, 1);
  EXPECT_EQ(m.fallback_periods, 0);
  expect_rmse(m, 0.0368, 0.0365, 0.0208);  // z: minus the bias (0.0021 without it)
  EXPECT_NEAR(m.rmse[5], 0.0087, 0.05 * 0.0087);  // psi: minus the bias (near zero without it)
  EXPECT_GT(biased.noise.bias[1] * biased.duration, 0.5);  // the true yaw integral's end value: past its bound
  Scenario noisy = biased;
  noisy.noise.white = test::shipped_scenario("noisy_sensors").noise.white;
  const MissionMetrics n = run_mission(test::noisy_artifact(), noisy, MissionOptions{});
  EXPECT_FALSE(n.diverged);
  EXPECT_EQ(n.state_constraint_violations, 0);
  EXPECT_EQ(n.fallback_periods, 0);
  EXPECT_NEAR(n.rmse[5], 0.0087, 0.1 * 0.0087);
}

// README "Noisy sensors": the output-feedback tube in its Gaussian form
// (config/tiltrotor_noisy_tube.yaml) tightens the state constraints by what the noise
// does to x - x_bar, flies the noisy sensors without a violation, and pays for it where
// forces exceed the box (the tighter sets soften more QPs; 3 N held aborted after 1045
// periods until the reversion past 4 times a bound, tube_law.revert_beyond, flew it:
// 82 periods on the tube gain's law).
TEST(Scenarios, TheGaussianOutputFeedbackTubeFliesTheNoiseAndIsTighterUnderForces) {
  const ControllerArtifact& a = test::noisy_tube_artifact();
  const ControllerArtifact& state_fb = test::noisy_artifact();
  EXPECT_NEAR(a.noise_margin, 2.46, 0.02 * 2.46);  // the sets hold 2.46 times the noise
  EXPECT_GT(a.estimation_error_radius.head(3).minCoeff(), 0.0);
  for (int i = 0; i < 3; ++i) {  // positions: tighter than the state-feedback design's
    EXPECT_LT(a.x_bar.half_width()(i), state_fb.x_bar.half_width()(i) - a.estimation_error_radius(i)) << i;
  }
  const MissionMetrics noisy = fly("noisy_sensors", a);
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.state_constraint_violations, 0);
  EXPECT_EQ(noisy.fallback_periods, 0);
  EXPECT_NEAR(static_cast<double>(noisy.softened_periods), 107.0, 0.1 * 107.0);
  expect_rmse(noisy, 0.0338, 0.0284, 0.0102);
  const MissionMetrics quiet = fly("thesis_helix", a);
  EXPECT_EQ(quiet.state_constraint_violations, 0);
  EXPECT_EQ(quiet.fallback_periods, 0);
  expect_rmse(quiet, 0.0277, 0.0273, 0.0101);
  const MissionMetrics gusts = fly("gusts", a);
  std::printf("gusts with the tube: softened %ld, worst %s %.3f\n", gusts.softened_periods,
              gusts.violation_worst_state.c_str(), gusts.violation_max_ratio);
  expect_softened_flight(gusts, 767.0, 1544.0);
  EXPECT_NEAR(gusts.violation_max_ratio, 1.37, 0.05 * 1.37);  // phi
  const MissionMetrics held = fly("sustained_force", a);  // 3 N from 10 s
  EXPECT_FALSE(held.diverged);
  EXPECT_EQ(held.periods, 6667);
  EXPECT_EQ(held.fallback_periods, held.reverted_periods);
  EXPECT_NEAR(static_cast<double>(held.reverted_periods), 82.0, 0.1 * 82.0);
  EXPECT_NEAR(static_cast<double>(held.state_constraint_violations), 5827.0, 0.05 * 5827.0);
  const MissionMetrics lost = test::fly_unreverted(test::shipped_scenario("sustained_force"), a);
  EXPECT_TRUE(lost.diverged);
  EXPECT_NEAR(static_cast<double>(lost.periods), 1045.0, 0.1 * 1045.0);  // 12.5 s
}

// README "Noisy sensors": the targets beyond issue 19's, twice the noise and 2 N gusts,
// measured and reported (not design points): the noisy-sensor design flies both to
// the end without a fallback period.
TEST(Scenarios, TwiceTheNoiseAndTwoNewtonGustsAreFlownAndReported) {
  // The filter-alone design (tiltrotor_noisy.yaml): its monitor reads the noise level
  // only, and the filter flies the gain for it (runtime/filter_gain_schedule.hpp): the
  // doubled noise without a violation, where the design's gain at every level gives 11
  // (a servo rate up to 1.20 times its bound).
  const ControllerArtifact& a = test::noisy_artifact();
  const MissionMetrics loud = fly("noisy_sensors_x2", a);
  EXPECT_FALSE(loud.diverged);
  EXPECT_EQ(loud.fallback_periods, 0);
  EXPECT_EQ(loud.state_constraint_violations, 0);
  EXPECT_EQ(loud.filter_noise_scale_max, 2.0);
  EXPECT_GT(loud.filter_louder_periods, loud.periods - 10);
  for (const char* servo_rate : {"d_alpha_l", "d_alpha_r"}) {  // 0.99 of their bound at most
    const std::size_t servo = static_cast<std::size_t>(
        std::find(loud.box_names.begin(), loud.box_names.end(), servo_rate) - loud.box_names.begin());
    ASSERT_LT(servo, loud.box_peak_ratio.size());
    EXPECT_LT(loud.box_peak_ratio[servo], 1.0) << servo_rate;
  }
  expect_rmse(loud, 0.0459, 0.0344, 0.0146);
  MissionOptions fixed;
  fixed.estimator.fixed_filter_gain = true;
  const MissionMetrics loud_fixed = run_mission(a, test::shipped_scenario("noisy_sensors_x2"), fixed);
  EXPECT_FALSE(loud_fixed.diverged);
  EXPECT_EQ(loud_fixed.fallback_periods, 0);
  EXPECT_EQ(loud_fixed.filter_louder_periods, 0);
  EXPECT_NEAR(static_cast<double>(loud_fixed.state_constraint_violations), 11.0, 0.1 * 11.0 + 2.0);
  EXPECT_NEAR(loud_fixed.violation_max_ratio, 1.20, 0.05 * 1.20);  // a servo rate
  EXPECT_NEAR(loud_fixed.rmse[0], 0.0464, 0.02 * 0.0464);
  EXPECT_NEAR(loud_fixed.rmse[1], 0.0353, 0.02 * 0.0353);
  EXPECT_NEAR(loud_fixed.rmse[2], 0.0124, 0.02 * 0.0124);
  expect_softened_flight(fly("gusts_2n", a), 1309.0, 1414.0);
  // Three and four times the noise (the twice-noise scenario's, scaled): 45 and 167
  // violations with the adaptive gain (servo rates up to 1.26 and 1.69 times their
  // bound), 201 and 724 with the design's (1.77, 2.37); flown to the end without a
  // fallback either way.
  const std::array<std::array<double, 5>, 2> louder = {{{1.5, 45.0, 1.26, 201.0, 1.77}, {2.0, 167.0, 1.69, 724.0, 2.37}}};
  for (const auto& [scale, violations, peak, fixed_violations, fixed_peak] : louder) {
    Scenario s = test::shipped_scenario("noisy_sensors_x2");
    for (double& w : s.noise.white) w *= scale;
    const MissionMetrics m = run_mission(a, s, MissionOptions{});
    const MissionMetrics fx = run_mission(a, s, fixed);
    std::printf("filter-alone design, %g times the noise: violations %ld (peak %.2f), the design's gain %ld (%.2f)\n",
                2.0 * scale, m.state_constraint_violations, m.violation_max_ratio, fx.state_constraint_violations,
                fx.violation_max_ratio);
    for (const MissionMetrics* f : {&m, &fx}) {
      EXPECT_FALSE(f->diverged) << scale;
      EXPECT_EQ(f->fallback_periods, 0) << scale;
    }
    EXPECT_NEAR(static_cast<double>(m.state_constraint_violations), violations, 0.15 * violations) << scale;
    EXPECT_NEAR(m.violation_max_ratio, peak, 0.05 * peak) << scale;
    EXPECT_NEAR(static_cast<double>(fx.state_constraint_violations), fixed_violations, 0.1 * fixed_violations) << scale;
    EXPECT_NEAR(fx.violation_max_ratio, fixed_peak, 0.05 * fixed_peak) << scale;
  }
  // The shipped design: its switched observer flies the doubled noise on the filter, with
  // the gain for twice the design's noise once the monitor reads it (runtime/
  // filter_gain_schedule.hpp): no violation (a servo rate at 0.998 of its bound, at the
  // 20 s step; 1 at 1.003 in the filter's start while the nominal started at the filter's
  // first estimate), where the design's gain at every level gives 12 (up to 1.20). The
  // residual observer alone puts a servo rate past its bound in most periods; the
  // flight goes on (with the tube gain of lambda's input weights it was aborted at once,
  // after 3 periods).
  const MissionMetrics shipped = fly("noisy_sensors_x2");
  EXPECT_FALSE(shipped.diverged);
  EXPECT_EQ(shipped.filtered_periods, shipped.periods);
  EXPECT_EQ(shipped.state_constraint_violations, 0);
  for (const char* servo_rate : {"d_alpha_l", "d_alpha_r"}) {  // 0.998 of their bound at most
    const std::size_t servo = static_cast<std::size_t>(
        std::find(shipped.box_names.begin(), shipped.box_names.end(), servo_rate) - shipped.box_names.begin());
    ASSERT_LT(servo, shipped.box_peak_ratio.size());
    EXPECT_LT(shipped.box_peak_ratio[servo], 1.0) << servo_rate;
  }
  EXPECT_EQ(shipped.filter_noise_scale_max, 2.0);
  EXPECT_GT(shipped.filter_louder_periods, shipped.periods - 10);  // all but the start's
  EXPECT_EQ(shipped.fallback_periods, 0);
  expect_rmse(shipped, 0.0458, 0.0343, 0.0141);
  const MissionMetrics design_gain = run_mission(test::artifact(), test::shipped_scenario("noisy_sensors_x2"), fixed);
  EXPECT_EQ(design_gain.filter_louder_periods, 0);
  EXPECT_NEAR(static_cast<double>(design_gain.state_constraint_violations), 12.0, 0.1 * 12.0 + 2.0);
  EXPECT_NEAR(design_gain.violation_max_ratio, 1.20, 0.05 * 1.20);
  // Three and four times the noise with the shipped design: 41 and 136 violations with the
  // adaptive gain, 214 and 733 with the design's (servo rates up to 1.25 and 1.67 times
  // their bound against 1.78 and 2.38), flown to the end without a fallback.
  const std::array<std::array<double, 5>, 2> shipped_louder = {{{1.5, 41.0, 1.25, 214.0, 1.78}, {2.0, 136.0, 1.67, 733.0, 2.38}}};
  for (const auto& [scale, violations, peak, fixed_violations, fixed_peak] : shipped_louder) {
    Scenario s = test::shipped_scenario("noisy_sensors_x2");
    for (double& w : s.noise.white) w *= scale;
    const MissionMetrics ad = run_mission(test::artifact(), s, MissionOptions{});
    const MissionMetrics fx = run_mission(test::artifact(), s, fixed);
    std::printf("shipped design, %g times the noise: violations %ld (peak %.2f), the design's gain %ld (%.2f)\n",
                2.0 * scale, ad.state_constraint_violations, ad.violation_max_ratio, fx.state_constraint_violations,
                fx.violation_max_ratio);
    EXPECT_FALSE(ad.diverged) << scale;
    EXPECT_EQ(ad.fallback_periods, 0) << scale;
    EXPECT_NEAR(static_cast<double>(ad.state_constraint_violations), violations, 0.15 * violations) << scale;
    EXPECT_NEAR(ad.violation_max_ratio, peak, 0.05 * peak) << scale;
    EXPECT_NEAR(static_cast<double>(fx.state_constraint_violations), fixed_violations, 0.1 * fixed_violations) << scale;
    EXPECT_NEAR(fx.violation_max_ratio, fixed_peak, 0.05 * fixed_peak) << scale;
  }
  const MissionMetrics raw = test::fly_residual_observer("noisy_sensors_x2");
  EXPECT_FALSE(raw.diverged);
  EXPECT_EQ(raw.periods, 6667);
  EXPECT_NEAR(static_cast<double>(raw.state_constraint_violations), 5658.0, 0.05 * 5658.0);
  // Its servo rates past 4 times their bound: the tube gain's law (revert_beyond) flies
  // 1645 periods, no other fallback (K_lqr there lost the vehicle in 26 periods).
  EXPECT_EQ(raw.fallback_periods, raw.reverted_periods);
  EXPECT_NEAR(static_cast<double>(raw.reverted_periods), 1645.0, 0.1 * 1645.0);
  EXPECT_NEAR(raw.violation_max_ratio, 9.99, 0.02 * 9.99);  // a servo rate, at the simulator's 10
  expect_softened_flight(fly("gusts_2n"), 1312.0, 1414.0);
}


// README "Noisy sensors" (config/scenarios/gusts_only.yaml): the 1.5 N gusts without the
// thesis' steps. Seeds 1, 2 and 3 (the file's) fly without a violation and without a
// fallback (seed 3 left the box by 0.3 % (d_x) for 7 periods at 34 s with the tube gain
// of lambda's input weights).
TEST(Scenarios, TheGustsAloneAreFlownWithoutAViolation) {
  const Scenario gusts = test::shipped_scenario("gusts_only");
  ASSERT_EQ(gusts.disturbances.events().size(), 1u);
  ASSERT_EQ(gusts.disturbances.events()[0].seed, 3u);
  for (std::uint32_t seed : {1u, 2u, 3u}) {
    Scenario s = gusts;
    std::vector<DisturbanceEvent> events = s.disturbances.events();
    events[0].seed = seed;
    s.disturbances = DisturbanceProfile(events);
    const MissionMetrics m = run_mission(test::artifact(), s, MissionOptions{});
    std::printf("gusts_only, seed %u: RMSE %.4f %.4f %.4f, violations %ld\n", seed, m.rmse[0], m.rmse[1], m.rmse[2],
                m.state_constraint_violations);
    EXPECT_FALSE(m.diverged) << seed;
    EXPECT_EQ(m.state_constraint_violations, 0) << seed;
    EXPECT_EQ(m.fallback_periods, 0) << seed;
  }
}

// README "Noisy sensors" and "Reverting past the model's region": the force envelope. A
// sustained 4 N force on the load aborts the shipped design's softened MPC within 0.9 s
// of its start (its swing transient) without the reversion (revert_beyond 0); with it
// (shipped: past 4 times a bound, back within 1.5) the tube gain's law flies 90 periods
// of the transient and the MPC the rest. The noisy-sensor design's with its filter's
// steady gain is lost either way; the filter that reads the step in its innovations
// flew it without the reversion too (the vertical speed 9.88 times its bound in the
// transient, the simulator's box at 10), now with 92 reverted periods; with soft
// constraints off, the LQR fallback rides it out, on the residual observer alone and on
// the switched observer, whose monitor skips the fallback's periods (reading them, it
// took the fallback's transient for 0.081 of the design noise, brought the filter in and
// its slower force estimate lost the flight).
TEST(Scenarios, ASustainedFourNewtonForceIsPastTheEnvelope) {
  const MissionMetrics shipped = fly("sustained_force_4n");
  EXPECT_FALSE(shipped.diverged);
  EXPECT_EQ(shipped.periods, 6667);
  EXPECT_EQ(shipped.fallback_periods, shipped.reverted_periods);
  EXPECT_NEAR(static_cast<double>(shipped.reverted_periods), 90.0, 0.1 * 90.0);
  EXPECT_NEAR(static_cast<double>(shipped.state_constraint_violations), 5831.0, 0.05 * 5831.0);
  const MissionMetrics unreverted = test::fly_unreverted(test::shipped_scenario("sustained_force_4n"));
  EXPECT_TRUE(unreverted.diverged);
  EXPECT_NEAR(static_cast<double>(unreverted.periods), 896.0, 25.0);  // 10.75 s
  EXPECT_EQ(unreverted.reverted_periods, 0);
  MissionOptions steady;
  steady.estimator.no_step_detection = true;
  const MissionMetrics lost = run_mission(test::noisy_artifact(), test::shipped_scenario("sustained_force_4n"), steady);
  EXPECT_TRUE(lost.diverged);
  EXPECT_NEAR(static_cast<double>(lost.periods), 902.0, 25.0);
  const MissionMetrics noisy = fly("sustained_force_4n", test::noisy_artifact());
  EXPECT_FALSE(noisy.diverged);
  EXPECT_EQ(noisy.periods, 6667);
  EXPECT_EQ(noisy.fallback_periods, noisy.reverted_periods);
  EXPECT_NEAR(static_cast<double>(noisy.reverted_periods), 92.0, 0.1 * 92.0);
  EXPECT_EQ(noisy.step_detections, 1);
  EXPECT_NEAR(static_cast<double>(noisy.state_constraint_violations), 5828.0, 0.05 * 5828.0);
  EXPECT_NEAR(noisy.violation_max_ratio, 9.88, 0.05 * 9.88);
  ControllerArtifact hard = test::artifact();
  hard.soft_constraints = false;
  hard.soft_penalty = 0.0;
  MissionOptions residual;
  residual.estimator.observer = "residual";
  const MissionMetrics lqr = run_mission(hard, test::shipped_scenario("sustained_force_4n"), residual);
  std::printf("soft constraints off, residual observer: diverged %d, fallbacks %ld\n", lqr.diverged, lqr.fallback_periods);
  EXPECT_FALSE(lqr.diverged);
  EXPECT_NEAR(static_cast<double>(lqr.fallback_periods), 5831.0, 0.05 * 5831.0);
  const MissionMetrics switched = fly("sustained_force_4n", hard);
  std::printf("soft constraints off, switched observer: filter %ld periods, level max %.4f\n", switched.filtered_periods,
              switched.noise_level_max);
  EXPECT_FALSE(switched.diverged);
  EXPECT_EQ(switched.filtered_periods, 7);
  EXPECT_NEAR(static_cast<double>(switched.fallback_periods), 5831.0, 0.05 * 5831.0);
}

// README "Noisy sensors", noise the design was not told about: the issue's own probes
// (0.1 degree on the angles alone: 2723 servo-rate violations before the filter; 1 cm and
// 0.5 degree: the mission aborted), a gyro alone (0.05 rad/s) and three times the noisy
// scenario's noise (15 mm, 0.9 degree). The shipped design's noise monitor reads each as
// noise (its level against the design's: the largest state group's) and keeps the
// filter, with the gain for the level it reads (filter_gain_schedule.hpp): no abort, and
// violations only at three times the noise, where the residual observer alone loses
// the flight.
TEST(Scenarios, NoiseOnOneSensorOrBeyondTheDesignsIsReadAndFlown) {
  struct Probe {
    const char* what;
    std::array<double, 4> white;  // position m, angle rad, velocity m/s, rate rad/s
    double violations, level;
  };
  const Probe probes[] = {
      {"0.1 deg on the angles alone", {0.0, 0.001745, 0.0, 0.0}, 0.0, 0.407},
      {"1 cm and 0.5 deg", {0.01, 0.00873, 0.0, 0.0}, 0.0, 2.669},
      {"a gyro alone, 0.05 rad/s", {0.0, 0.0, 0.0, 0.05}, 0.0, 1.519},
      {"three times the noisy scenario's", {0.015, 0.01572, 0.093, 0.099}, 42.0, 5.58},  // 213 with the design's gain
  };
  for (const Probe& p : probes) {
    Scenario sc = test::shipped_scenario("noisy_sensors");
    sc.noise.white = p.white;
    const MissionMetrics m = run_mission(test::artifact(), sc, MissionOptions{});
    std::printf("%s: violations %ld (worst %s %.2f), filter %ld of %ld periods, level max %.3f, RMSE %.4f %.4f %.4f%s\n",
                p.what, m.state_constraint_violations, m.violation_worst_state.c_str(), m.violation_max_ratio,
                m.filtered_periods, m.periods, m.noise_level_max, m.rmse[0], m.rmse[1], m.rmse[2],
                m.diverged ? ", DIVERGED" : "");
    EXPECT_FALSE(m.diverged) << p.what;
    EXPECT_EQ(m.fallback_periods, 0) << p.what;
    EXPECT_EQ(m.filtered_periods, m.periods) << p.what;  // read as noise from the first check on
    EXPECT_NEAR(m.noise_level_max, p.level, 0.05 * p.level) << p.what;
    EXPECT_NEAR(static_cast<double>(m.state_constraint_violations), p.violations, 0.05 * p.violations) << p.what;
    if (p.white[0] == 0.015) {
      EXPECT_NEAR(m.violation_max_ratio, 1.25, 0.05 * 1.25);  // a servo rate (1.78 with the design's gain)
      EXPECT_EQ(m.violation_worst_state, "d_alpha_r");
      EXPECT_EQ(m.filter_noise_scale_max, 4.0);  // the filter's gain for the noise it reads
      MissionOptions residual;
      residual.estimator.observer = "residual";
      const MissionMetrics raw = run_mission(test::artifact(), sc, residual);
      std::printf("  residual observer alone: violations %ld, diverged %d after %ld periods\n",
                  raw.state_constraint_violations, raw.diverged, raw.periods);
      EXPECT_TRUE(raw.diverged);
      EXPECT_NEAR(static_cast<double>(raw.periods), 968.0, 50.0);  // 11.6 s
    }
  }
}

// README "Noisy sensors": the noisy scenario's noise (5 mm, 0.3 degree, seed 4) on the
// other shipped tracks, flown by the shipped design: read as noise from the first check,
// no violation.
TEST(Scenarios, TheShippedDesignFliesTheNoiseOnTheOtherTracks) {
  const NoiseSpec noise = test::shipped_scenario("noisy_sensors").noise;
  const struct {
    const char* name;
    double x, y, z;
  } tracks[] = {{"figure_eight", 0.0346, 0.0282, 0.0097}, {"waypoints", 0.0287, 0.0274, 0.0059}, {"lissajous_csv", 0.0363, 0.0117, 0.0058}};
  for (const auto& t : tracks) {
    Scenario sc = test::shipped_scenario(t.name);
    sc.noise = noise;
    const MissionMetrics m = run_mission(test::artifact(), sc, MissionOptions{});
    std::printf("%s with the noise: violations %ld, fallbacks %ld, filter %ld of %ld periods, RMSE %.4f %.4f %.4f\n",
                t.name, m.state_constraint_violations, m.fallback_periods, m.filtered_periods, m.periods, m.rmse[0],
                m.rmse[1], m.rmse[2]);
    EXPECT_FALSE(m.diverged) << t.name;
    EXPECT_EQ(m.state_constraint_violations, 0) << t.name;
    EXPECT_EQ(m.fallback_periods, 0) << t.name;
    EXPECT_EQ(m.filtered_periods, m.periods) << t.name;
    expect_rmse(m, t.x, t.y, t.z);
  }
}

// README "Noisy sensors", forces between the gusts and the 4 N abort: a sustained force
// on the load from 10 s (the helix, no steps) along x or y. At 2.5 N the violations end
// 2.8 s (x) and 1.6 s (y) after the step, the load's swing to its static tilt, inside
// the box (telemetry's in_state_box); 3.5 N is past the envelope (3 N: sustained_force)
// and flown to the end on the softened MPC, no LQR period (along x, 47 periods of the
// step's transient past 4 times a bound on the tube gain's law, revert_beyond: z RMSE
// 0.0137 m instead of 0.0082). Along x at 3.5 N the thrusts
// chatter between the rotors at their 30 N bound for a few periods after the step; the
// noise monitor read that as 4 times the design's noise and brought the filter in for
// 10.6 s, whose slower force estimate swung the vertical speed (z RMSE 0.074 m). It now
// skips the periods the softened QP or the fallback flew (tube_controller.hpp): the
// residual observer flies on, as it alone would.
TEST(Scenarios, SustainedForcesUpToThreeAndAHalfNewtonsAreFlownToTheEnd) {
  struct Case {
    double force;
    int axis;
    double violations, softened, z_rmse, reverted;
  };
  const Case cases[] = {{2.5, 0, 197, 209, 0.0044, 0},
                        {2.5, 1, 123, 128, 0.0030, 0},
                        {3.5, 0, 5811, 5831, 0.0137, 47},
                        {3.5, 1, 5819, 5820, 0.0058, 0}};
  for (const Case& c : cases) {
    Scenario sc = test::shipped_scenario("sustained_force");
    DisturbanceEvent e;
    e.start = 10.0;
    e.force(c.axis) = c.force;
    sc.disturbances = DisturbanceProfile({e});
    const MissionMetrics m = run_mission(test::artifact(), sc, MissionOptions{});
    std::printf("%.1f N along %c: violations %ld, softened %ld, fallbacks %ld, filter %ld periods (level max %.4f), "
                "RMSE %.4f %.4f %.4f%s\n",
                c.force, "xy"[c.axis], m.state_constraint_violations, m.softened_periods, m.fallback_periods,
                m.filtered_periods, m.noise_level_max, m.rmse[0], m.rmse[1], m.rmse[2], m.diverged ? ", DIVERGED" : "");
    EXPECT_FALSE(m.diverged);
    EXPECT_EQ(m.fallback_periods, m.reverted_periods);  // no LQR period
    EXPECT_NEAR(static_cast<double>(m.reverted_periods), c.reverted, 0.1 * c.reverted + 2.0);
    EXPECT_NEAR(static_cast<double>(m.state_constraint_violations), c.violations, 0.05 * c.violations);
    EXPECT_NEAR(static_cast<double>(m.softened_periods), c.softened, 0.05 * c.softened);
    EXPECT_EQ(m.filtered_periods, 7);  // the first check only
    EXPECT_LT(m.noise_level_max, 0.025);  // below residual_below: far from filter_above
    EXPECT_NEAR(m.rmse[2], c.z_rmse, 0.05 * c.z_rmse);
    if (c.reverted > 0) {  // without the reversion: softened to the end, z RMSE 0.0082 m
      const MissionMetrics soft = test::fly_unreverted(sc);
      EXPECT_FALSE(soft.diverged);
      EXPECT_EQ(soft.fallback_periods, 0);
      EXPECT_NEAR(soft.rmse[2], 0.0082, 0.05 * 0.0082);
    }
  }
}

// README: masses and inertias +-30 % (config/scenarios/masses_30.yaml), the first three
// of the ten Monte Carlo draws with each design (the shipped one, its switched observer
// on the residual observer after the first check, and the noisy-sensor one), and all
// ten with the shipped design.
TEST(Scenarios, MassesThirtyPercentOffAsTheReadmeStates) {
  const Scenario sc = test::shipped_scenario("masses_30");
  auto fly_run = [&](const ControllerArtifact& a, int run) {
    MissionOptions o;
    o.run = run;
    const MissionMetrics m = run_mission(a, sc, o);
    EXPECT_FALSE(m.diverged);
    std::printf("masses_30 run %d (%s): violations %ld, fallbacks %ld, softened %ld\n", run, m.estimator.c_str(),
                m.state_constraint_violations, m.fallback_periods, m.softened_periods);
    return m;
  };
  // A count stated as 0 is asserted as 0; others to 10 % and 2 periods.
  auto near = [](long got, long want) {
    if (want == 0) {
      EXPECT_EQ(got, 0);
    } else {
      EXPECT_NEAR(static_cast<double>(got), static_cast<double>(want), 0.1 * want + 2.0);
    }
  };
  // violations and fallback periods per run: the shipped design, the noisy-sensor one.
  // (before the shipped design had soft constraints: 0, 4, 42 violations, 0, 15, 91 fallbacks)
  // (the noisy design before the filter's start prior: 0, 48, 57 violations)
  const long shipped_v[3] = {0, 0, 12}, shipped_f[3] = {0, 0, 0}, noisy_v[3] = {0, 15, 57}, noisy_f[3] = {0, 0, 0};
  const long shipped_s[3] = {0, 33, 101}, noisy_s[3] = {0, 0, 157};  // softened periods
  for (int run = 0; run < 3; ++run) {
    const MissionMetrics s = fly_run(test::artifact(), run), n = fly_run(test::noisy_artifact(), run);
    near(s.state_constraint_violations, shipped_v[run]);
    near(s.fallback_periods, shipped_f[run]);
    // The first check only: the mass error does not read as noise. Run 0: the first 85
    // periods; the filter's start swings the thrust while its first force estimates
    // settle, which the one-step residual of the mass-mismatched model reads as 0.06 of
    // the design noise (above filter_above) until the monitor's 1 s window forgets it.
    EXPECT_EQ(s.filtered_periods, run == 0 ? 85 : 7) << run;
    near(n.state_constraint_violations, noisy_v[run]);
    near(n.fallback_periods, noisy_f[run]);
    near(s.softened_periods, shipped_s[run]);
    near(n.softened_periods, noisy_s[run]);
  }
  // The target, zero violations in all ten runs with the default law, is
  // impossible in runs 2 and 9 (their light loads swing past d_x's bound after the 1 N
  // step whatever the vehicle does: cli.best-case); the shipped design violates in
  // those two only.
  for (int run = 3; run < 10; ++run) {
    const MissionMetrics s = fly_run(test::artifact(), run);
    near(s.state_constraint_violations, run == 9 ? 23 : 0);
    EXPECT_EQ(s.fallback_periods, 0) << run;
  }
}

// README "The filter's start": masses and inertias +-30 % with the noisy sensors
// (scenarios/masses_30_noisy.yaml), the first 5 s of the ten draws, where the unknown
// weight is read. With the start prior (tiltrotor.yaml estimation.start_prior) 70
// violations in all, 410 with the steady gain from the start (the prior zeroed).
TEST(Scenarios, TheFiltersStartReadsAnUnknownWeightThroughTheNoise) {
  const Scenario sc = test::shipped_scenario("masses_30_noisy");
  ControllerArtifact steady = test::artifact();
  ASSERT_TRUE(steady.filter_start_scheduled());
  steady.estimator_start.setZero();
  long with_start = 0, without = 0;
  double worst_with = 0.0, worst_without = 0.0;
  for (int run = 0; run < 10; ++run) {
    MissionOptions o;
    o.run = run;
    o.duration = 5.0;
    const MissionMetrics s = run_mission(test::artifact(), sc, o), n = run_mission(steady, sc, o);
    EXPECT_FALSE(s.diverged || n.diverged) << run;
    EXPECT_EQ(s.fallback_periods, 0) << run;
    std::printf("masses_30_noisy run %d, 5 s: violations %ld (peak %.2f %s), steady gain %ld (peak %.2f %s)\n", run,
                s.state_constraint_violations, s.violation_max_ratio, s.violation_worst_state.c_str(),
                n.state_constraint_violations, n.violation_max_ratio, n.violation_worst_state.c_str());
    with_start += s.state_constraint_violations;
    without += n.state_constraint_violations;
    worst_with = std::max(worst_with, s.violation_max_ratio);
    worst_without = std::max(worst_without, n.violation_max_ratio);
  }
  EXPECT_NEAR(static_cast<double>(with_start), 70.0, 8.0) << "README states 70";
  EXPECT_NEAR(static_cast<double>(without), 410.0, 41.0) << "README states 410";
  EXPECT_NEAR(worst_with, 1.38, 0.05) << "README states 1.38";
  EXPECT_NEAR(worst_without, 2.07, 0.05) << "README states 2.07";
  // The schedule's length (README: 106 periods, 1.27 s).
  const KalmanDesign k = kalman_model(test::artifact());
  const ControllerArtifact& a = test::artifact();
  EXPECT_EQ(start_gains(k, start_covariance(k, a.D.cols(), a.estimator_start(0), a.estimator_start(1),
                                            a.estimator_start(2))).size(), 106u);
}

}  // namespace
}  // namespace tmpc

namespace tmpc {
namespace {

// README "Scenarios": a start off the reference (scenarios/start_offset.yaml: 0.6, 0.5
// and 0.4 m, 0.05 rad, the thesis' steps) is joined from where the vehicle is
// (runtime/reference_join.hpp): no violation, no softened QP, no fallback. Straight to
// the mission's reference (reference_join off) the hard QP is infeasible at the start
// and the softened law flies the load past its speed bound. A hover started 0.9 m off
// along x, nearly the whole position box, is joined the same way.
TEST(Scenarios, AStartOffTheReferenceIsJoinedWithoutAViolation) {
  const MissionMetrics joined = test::fly("start_offset");
  EXPECT_FALSE(joined.diverged);
  EXPECT_EQ(joined.state_constraint_violations, 0);
  EXPECT_EQ(joined.softened_periods, 0);
  EXPECT_EQ(joined.fallback_periods, 0);
  EXPECT_NEAR(joined.max_abs_error[0], 0.6, 2e-3);  // the start
  ASSERT_EQ(joined.join_offset.size(), 3u);
  EXPECT_NEAR(joined.join_offset[0], -0.6, 1e-3);
  EXPECT_NEAR(joined.join_offset[2], -0.4, 1e-3);
  EXPECT_NEAR(joined.join_duration, 1.875 * joined.join_offset[2] / (-0.25 * 0.2), 1e-9);  // 15 s: z's speed bound
  const double rmse[3] = {0.166, 0.139, 0.108};  // the README's table: the join counted
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(joined.rmse[static_cast<std::size_t>(i)], rmse[i], 0.02 * rmse[i]) << i;
  MissionOptions o;
  o.reference_join = false;
  const MissionMetrics straight = run_mission(test::artifact(), test::shipped_scenario("start_offset"), o);
  std::printf("without the join: violations %ld (worst %s %.2f), softened %ld\n", straight.state_constraint_violations,
              straight.violation_worst_state.c_str(), straight.violation_max_ratio, straight.softened_periods);
  EXPECT_NEAR(straight.state_constraint_violations, 72, 4);  // the README's counts, to 5 %
  EXPECT_NEAR(straight.softened_periods, 97, 5);
  EXPECT_EQ(straight.violation_worst_state, "d_x");
  EXPECT_NEAR(straight.violation_max_ratio, 1.60, 0.05);
  Scenario hover = test::shipped_scenario("start_offset");
  hover.trajectory = make_hover(HoverShape{Eigen::Vector3d(0, 0, 2), 0.0});
  hover.start_position_offset = Eigen::Vector3d(0.9, 0.0, 0.0);
  hover.start_yaw_offset = 0.0;
  hover.disturbances = DisturbanceProfile(std::vector<DisturbanceEvent>{});
  o.reference_join = true;
  o.duration = 25.0;
  const MissionMetrics far = run_mission(test::artifact(), hover, o);
  std::printf("hover 0.9 m off: violations %ld (worst %s %.2f), softened %ld, x RMSE %.3f m\n", far.state_constraint_violations,
              far.violation_worst_state.c_str(), far.violation_max_ratio, far.softened_periods, far.rmse[0]);
  EXPECT_EQ(far.state_constraint_violations, 0);
  EXPECT_EQ(far.softened_periods, 0);
  hover.start_position_offset = Eigen::Vector3d(0.4, 0.0, 0.0);
  o.reference_join = false;
  const MissionMetrics near = run_mission(test::artifact(), hover, o);
  std::printf("hover 0.4 m off, straight: violations %ld (worst %s %.2f), softened %ld\n", near.state_constraint_violations,
              near.violation_worst_state.c_str(), near.violation_max_ratio, near.softened_periods);
  EXPECT_GT(near.state_constraint_violations, 0);  // past the speed bound too
  EXPECT_EQ(near.violation_worst_state, "d_x");
}

// README "Sensor glitches": the thesis mission with the noisy sensors and glitches (0.3 m
// on a position sample with probability 0.002, 0.2 rad on an angle with 0.001;
// config/scenarios/glitches.yaml). The filter's innovation gate replaces each by its
// prediction (tube_controller.hpp): no violation, the noise read at the design's level
// (the glitches let through read as 5.7 times it and brought the louder gains), the
// RMSE of the flight without glitches; without the gate 19 violations, servo rates 1.5
// times their bound. On clean sensors the residual observer flies and the gate guards
// it: the thesis mission's RMSE, where without the gate the glitches read as noise,
// brought the filter in and kicked a servo rate to 2.9 times its bound.
TEST(Scenarios, SensorGlitchesAreReplacedByTheFiltersPrediction) {
  auto servo_peak = [](const MissionMetrics& m) {
    double peak = 0.0;
    for (std::size_t i = 0; i < m.box_names.size(); ++i) {
      if (m.box_names[i] == "d_alpha_r" || m.box_names[i] == "d_alpha_l") peak = std::max(peak, m.box_peak_ratio[i]);
    }
    return peak;
  };
  MissionOptions open;
  open.estimator.no_innovation_gate = true;
  const Scenario noisy = test::shipped_scenario("glitches");
  Scenario clean = noisy;
  clean.noise.white = {0.0, 0.0, 0.0, 0.0};
  // Expected glitches: 6667 periods x (3 positions x 0.002 + 7 angles x 0.001) = 87.
  const double expected = 6667.0 * (3 * 0.002 + 7 * 0.001), sd = std::sqrt(expected);
  struct Case {
    const char* what;
    const Scenario* s;
    const ControllerArtifact* a;
    double rmse_x, rmse_y, rmse_z;  // with the gate
    bool filter;                    // the filter flies (else the residual observer)
    double open_violations, open_peak;
  };
  const Case cases[] = {
      {"shipped, noisy", &noisy, &test::artifact(), 0.0346, 0.0283, 0.0096, true, 19.0, 1.50},
      {"shipped, clean", &clean, &test::artifact(), 0.0308, 0.0300, 0.00225, false, 26.0, 2.92},
      {"filter alone, noisy", &noisy, &test::noisy_artifact(), 0.0348, 0.0284, 0.0102, true, 12.0, 1.44},
  };
  for (const Case& c : cases) {
    const MissionMetrics g = run_mission(*c.a, *c.s, MissionOptions{});
    const MissionMetrics o = run_mission(*c.a, *c.s, open);
    std::printf("%s: gated %ld, violations %ld (servo-rate peak %.2f); without the gate %ld (%.2f), noise level up to "
                "%.2f\n", c.what, g.gated_samples, g.state_constraint_violations, servo_peak(g),
                o.state_constraint_violations, servo_peak(o), o.noise_level_max);
    EXPECT_NEAR(static_cast<double>(g.gated_samples), expected, 4.0 * sd) << c.what;
    EXPECT_EQ(g.state_constraint_violations, 0) << c.what;
    EXPECT_EQ(g.fallback_periods, 0) << c.what;
    EXPECT_FALSE(g.diverged) << c.what;
    EXPECT_LT(servo_peak(g), 0.85) << c.what;
    EXPECT_EQ(g.filter_louder_periods, 0) << c.what << ": a glitch read as louder noise";
    EXPECT_EQ(g.filtered_periods > g.periods / 2, c.filter) << c.what;
    expect_rmse(g, c.rmse_x, c.rmse_y, c.rmse_z);
    EXPECT_EQ(o.gated_samples, 0) << c.what;
    EXPECT_NEAR(static_cast<double>(o.state_constraint_violations), c.open_violations, 0.2 * c.open_violations) << c.what;
    EXPECT_NEAR(servo_peak(o), c.open_peak, 0.05 * c.open_peak) << c.what;
  }
}

// Actuator faults the controller is not told of (README "Actuator faults"): the right
// rotor at 85 % of its thrust from 30 s, 0.003 N m on the left servo's torque from 50 s,
// with the thesis' steps. The offset-free observer takes both as disturbances: no
// violation, no fallback, and no measurement read as a glitch (before the innovation
// gate required a glitch to arrive in one period, the filter's lag of the thrust loss
// passed the gate after 0.24 s, and the replaced rows gave 32 violations, the servo
// rates 1.6 times their bound, and a noise level of 0.58 that brought the filter in).
TEST(Scenarios, ActuatorFaultsTheControllerIsNotToldOfAreFlown) {
  const MissionMetrics m = fly("actuator_faults");
  EXPECT_FALSE(m.diverged);
  EXPECT_EQ(m.periods, 6667);
  EXPECT_EQ(m.state_constraint_violations, 0);
  EXPECT_EQ(m.fallback_periods, 0);
  EXPECT_EQ(m.gated_samples, 0);
  EXPECT_LT(m.noise_level_max, 0.01);
  expect_rmse(m, 0.0308, 0.0374, 0.0044);
  EXPECT_EQ(m.window_starts, (std::vector<double>{0.0, 20.0, 30.0, 40.0, 50.0, 60.0}));  // the faults' onsets too
  // With the noisy sensors (the filter flying): the thrust loss is detected as a step in
  // the filter's innovations, which re-opens its disturbance covariance (README
  // "Actuator faults"); its steady gain alone reads the loss over about a second.
  const Scenario noisy = test::shipped_scenario("actuator_faults_noisy");
  EXPECT_EQ(noisy.noise.white, test::shipped_scenario("noisy_sensors").noise.white);
  EXPECT_EQ(noisy.noise.seed, test::shipped_scenario("noisy_sensors").noise.seed);
  EXPECT_EQ(noisy.faults.size(), test::shipped_scenario("actuator_faults").faults.size());
  const MissionMetrics detected = run_mission(test::artifact(), noisy, MissionOptions{});
  MissionOptions steady, keep, gains, every;
  steady.estimator.no_step_detection = true;
  keep.estimator.step_reopens_lift = false;
  gains.estimator.step_corrects_input = false;
  every.estimator.late_step_keeps_gain = false;
  const MissionMetrics slow = run_mission(test::artifact(), noisy, steady);
  const MissionMetrics kept = run_mission(test::artifact(), noisy, keep);
  const MissionMetrics reopened = run_mission(test::artifact(), noisy, gains);
  const MissionMetrics all = run_mission(test::artifact(), noisy, every);
  std::printf("actuator_faults, noisy sensors: %ld violations (%ld steps re-opened, %ld the lift, %ld read as the "
              "actuators', %ld left to the steady gain; worst %.2f), %ld re-opening late steps too (%ld; worst %.2f), %ld "
              "with the re-opened gains alone (%ld, %ld left; worst %.2f), %ld with the lift kept (worst %.2f), %ld with "
              "the steady gain alone (worst %.2f)\n",
              detected.state_constraint_violations, detected.step_detections, detected.step_lift_reopenings,
              detected.step_actuator_corrections, detected.step_late_kept, detected.violation_max_ratio,
              all.state_constraint_violations, all.step_detections, all.violation_max_ratio,
              reopened.state_constraint_violations, reopened.step_detections, reopened.step_late_kept,
              reopened.violation_max_ratio, kept.state_constraint_violations, kept.violation_max_ratio,
              slow.state_constraint_violations, slow.violation_max_ratio);
  EXPECT_FALSE(detected.diverged);
  EXPECT_EQ(detected.fallback_periods, 0);
  EXPECT_LE(detected.state_constraint_violations, 2) << "README states 1";
  EXPECT_NEAR(static_cast<double>(all.state_constraint_violations), 8.0, 3.0) << "README states 8";
  EXPECT_NEAR(static_cast<double>(reopened.state_constraint_violations), 13.0, 4.0) << "README states 13";
  EXPECT_NEAR(static_cast<double>(kept.state_constraint_violations), 30.0, 0.2 * 30.0) << "README states 30";
  EXPECT_NEAR(detected.violation_max_ratio, 1.34, 0.1) << "README states 1.34";
  EXPECT_NEAR(all.violation_max_ratio, 1.47, 0.1) << "README states 1.47";
  EXPECT_LT(reopened.violation_max_ratio, 1.6);
  EXPECT_LT(kept.violation_max_ratio, 1.6);  // 1.46 (2.58 with the steady gain alone)
  EXPECT_NEAR(static_cast<double>(slow.state_constraint_violations), 142.0, 0.05 * 142.0) << "README states 142";
  // Read (telemetry, measured once), by default: the thrust loss at 30.04 s (the
  // actuators' step: the filter's prediction corrected, the lift re-opened); the servo's
  // torque bias at 50.29 s and the 1 N vertical step at 61.02 s are older than the
  // detection window and left to the steady gain (re-opened, as --reopen-late-steps
  // does, the servo's rate swung to 1.47 times its bound after the steady gain had
  // brought it back); the 1 N y step at 40 s is not read. With the re-opened gains alone
  // the y step is read at 40.12 s too (horizontal: the lift kept).
  EXPECT_EQ(detected.step_detections, 1) << "the thrust loss";
  EXPECT_EQ(detected.step_actuator_corrections, 1) << "the thrust loss";
  EXPECT_EQ(detected.step_lift_reopenings, 1);
  EXPECT_EQ(detected.step_late_kept, 2) << "the servo's bias and the vertical step, both older than the window";
  EXPECT_GE(all.step_detections, 3);
  EXPECT_EQ(all.step_actuator_corrections, 1);
  EXPECT_EQ(all.step_late_kept, 0);
  EXPECT_EQ(reopened.step_actuator_corrections, 0);
  EXPECT_GE(reopened.step_lift_reopenings, 1);
  EXPECT_EQ(reopened.step_detections - reopened.step_lift_reopenings, 1) << "the y step, horizontal";
  EXPECT_EQ(reopened.step_late_kept, 1) << "the vertical step at 61.02 s";
  EXPECT_EQ(kept.step_lift_reopenings, 0);
  EXPECT_EQ(kept.step_actuator_corrections, 0) << "the actuators' class needs the lift's classification";
  EXPECT_EQ(kept.step_late_kept, 0) << "so does a step left to the steady gain";
  EXPECT_EQ(slow.step_detections, 0);
}

// README "Re-opening the lift at a step". The thesis mission's first 40 s with 1.5
// times the noisy sensors' noise and the left rotor at 90 % of its thrust from 25 s:
// the step is read in both flights; with the force kept (--step-keeps-lift) its
// steady gain reads the lost lift slowly and the vertical speed passes its bound (8
// violations, d_z 1.03 times its bound); classified as not horizontal, the vertical
// force re-opened, the flight has none (d_z 0.66 with the re-opened gains alone,
// --no-actuator-step; 0.53 by default, the step read as the actuators' too). The same
// flight without the fault reads no step.
TEST(Scenarios, ReopeningTheLiftAtAStepHoldsTheVerticalSpeedThroughARotorFault) {
  Scenario s = test::shipped_scenario("thesis_helix");
  s.duration = 40.0;
  s.noise = test::shipped_scenario("noisy_sensors").noise;
  for (double& w : s.noise.white) w *= 1.5;
  const MissionMetrics clean = run_mission(test::artifact(), s, MissionOptions{});
  s.faults = {ActuatorFault{ActuatorFault::Kind::Efficiency, 1, 0.9, 0.0, 25.0}};
  MissionOptions keep, gains;
  keep.estimator.step_reopens_lift = false;
  gains.estimator.step_corrects_input = false;
  const MissionMetrics kept = run_mission(test::artifact(), s, keep);
  const MissionMetrics opened = run_mission(test::artifact(), s, gains);
  const MissionMetrics corrected = run_mission(test::artifact(), s, MissionOptions{});
  const auto dz = static_cast<std::size_t>(std::find(kept.box_names.begin(), kept.box_names.end(), "d_z") -
                                           kept.box_names.begin());
  ASSERT_LT(dz, kept.box_peak_ratio.size());
  std::printf("rotor at 90 %% with 1.5 times the noise: %ld violations (d_z %.2f of its bound) with the force kept, %ld "
              "(d_z %.2f) with the lift re-opened, %ld (d_z %.2f) read as the actuators' too\n",
              kept.state_constraint_violations, kept.box_peak_ratio[dz], opened.state_constraint_violations,
              opened.box_peak_ratio[dz], corrected.state_constraint_violations, corrected.box_peak_ratio[dz]);
  EXPECT_EQ(clean.step_detections, 0);
  EXPECT_EQ(kept.step_detections, 1);
  EXPECT_EQ(opened.step_detections, 1);
  EXPECT_EQ(opened.step_lift_reopenings, 1);
  EXPECT_EQ(kept.step_lift_reopenings, 0);
  EXPECT_NEAR(static_cast<double>(kept.state_constraint_violations), 8.0, 3.0);
  EXPECT_NEAR(kept.box_peak_ratio[dz], 1.03, 0.05 * 1.03);
  EXPECT_EQ(opened.state_constraint_violations, 0);
  EXPECT_NEAR(opened.box_peak_ratio[dz], 0.66, 0.05 * 0.66);
  EXPECT_EQ(opened.fallback_periods, 0);
  EXPECT_FALSE(opened.diverged);
  EXPECT_EQ(corrected.step_actuator_corrections, 1);
  EXPECT_EQ(corrected.state_constraint_violations, 0);
  EXPECT_NEAR(corrected.box_peak_ratio[dz], 0.53, 0.05 * 0.53);
  EXPECT_EQ(corrected.fallback_periods, 0);
}

}  // namespace
}  // namespace tmpc
