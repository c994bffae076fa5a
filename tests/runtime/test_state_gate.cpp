// The plausibility gate on a double integrator (position, velocity; T = 0.1 s) whose
// frames come from the same model: consistent frames pass, a jump of 1.1 thresholds
// is rejected and one of 0.9 passes, a sustained jump is adopted after three frames,
// time stamps must advance with the sequence, the yaw wraps, and the defaults derive
// from the error box.
#include <cmath>

#include <gtest/gtest.h>

#include "tmpc/runtime/state_gate.hpp"

namespace tmpc {
namespace {

constexpr double kT = 0.1;

struct Integrator {
  Eigen::MatrixXd A = (Eigen::MatrixXd(2, 2) << 1.0, kT, 0.0, 1.0).finished();
  Eigen::MatrixXd B = (Eigen::MatrixXd(2, 1) << 0.5 * kT * kT, kT).finished();
  // Normalization by half-widths 2 m and 1 m/s, input range [-4, 4] (N_u = 0.25).
  Eigen::VectorXd N_x = (Eigen::VectorXd(2) << 0.5, 1.0).finished();
  Eigen::VectorXd N_u = Eigen::VectorXd::Constant(1, 0.25);
  // The normalized model: x_n+ = (N A N^-1) x_n + (N B N_u^-1) u_n.
  Eigen::MatrixXd An() const { return N_x.asDiagonal() * A * N_x.cwiseInverse().asDiagonal(); }
  Eigen::MatrixXd Bn() const { return N_x.asDiagonal() * B * (1.0 / N_u(0)); }
};

StateGate make_gate(const Integrator& m, int horizon = 50) {
  StateGateSettings s;
  s.period = kT;
  s.jump = (Eigen::VectorXd(2) << 0.2, 0.1).finished();
  s.horizon = horizon;
  return StateGate(m.An(), m.Bn(), m.N_x, m.N_u, {StateKind::Position, StateKind::Velocity}, s);
}

TEST(StateGate, FramesOfTheModelPassAndAJumpBeyondItsThresholdDoesNot) {
  const Integrator m;
  StateGate g = make_gate(m);
  Eigen::VectorXd x = (Eigen::VectorXd(2) << 0.3, -0.2).finished();
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(1, 1.5);
  EXPECT_EQ(g.check(0.0, 1, x, u), StateGate::Verdict::First);
  for (int k = 1; k <= 20; ++k) {
    x = m.A * x + m.B * u;
    EXPECT_EQ(g.check(kT * k, static_cast<std::uint32_t>(k + 1), x, u), StateGate::Verdict::Accepted) << k;
  }
  // 0.9 and 1.1 times the position threshold (0.2 m) against the prediction.
  Eigen::VectorXd next = m.A * x + m.B * u;
  Eigen::VectorXd off = next;
  off(0) += 0.22;
  EXPECT_EQ(g.check(kT * 21, 22, off, u), StateGate::Verdict::RejectedJump);
  // The next frame is two periods after the last accepted one: predicted over two steps.
  {
    StateGate g2 = g;  // the same frame 1.2 thresholds off is still refused
    Eigen::VectorXd n2 = m.A * (m.A * x + m.B * u) + m.B * u;
    n2(1) += 1.2 * 0.1 * 1.1;
    EXPECT_EQ(g2.check(kT * 22, 23, n2, u), StateGate::Verdict::RejectedJump);
  }
  next = m.A * next + m.B * u;
  off = next;
  off(1) += 0.9 * 0.1 * 1.1;  // 0.9 of the velocity threshold, grown by 10 % for the second period
  EXPECT_EQ(g.check(kT * 22, 23, off, u), StateGate::Verdict::Accepted);
  EXPECT_EQ(g.counts()[io::Reject::Jump], 1);
  EXPECT_EQ(g.counts().accepted, 22);
}

TEST(StateGate, ASustainedJumpIsAdoptedAfterThreeConsistentFrames) {
  const Integrator m;
  StateGate g = make_gate(m);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  g.check(0.0, 1, x, u);
  x(0) = 1.0;  // the estimator reset: 1 m away, and it stays there
  EXPECT_EQ(g.check(kT, 2, x, u), StateGate::Verdict::RejectedJump);
  EXPECT_EQ(g.check(2 * kT, 3, x, u), StateGate::Verdict::RejectedJump);
  EXPECT_EQ(g.check(3 * kT, 4, x, u), StateGate::Verdict::Resynced);
  EXPECT_EQ(g.check(4 * kT, 5, x, u), StateGate::Verdict::Accepted);
  EXPECT_EQ(g.counts().resyncs, 1);
  // Inconsistent outliers (alternating far values) never form a track.
  for (int k = 0; k < 10; ++k) {
    Eigen::VectorXd y = x;
    y(0) += (k % 2 == 0 ? 5.0 : -5.0);
    EXPECT_FALSE(StateGate::accepted(g.check((5 + k) * kT, static_cast<std::uint32_t>(6 + k), y, u)));
  }
  EXPECT_EQ(g.counts().resyncs, 1);
}

TEST(StateGate, TimeStampsMustAdvanceWithTheSequence) {
  const Integrator m;
  StateGate g = make_gate(m);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(2), u = Eigen::VectorXd::Zero(1);
  g.check(1.0, 10, x, u);
  EXPECT_EQ(g.check(1.0, 11, x, u), StateGate::Verdict::RejectedTime);         // no advance
  EXPECT_EQ(g.check(1.0 - 10.0, 12, x, u), StateGate::Verdict::RejectedTime);  // 10 s in the past
  EXPECT_EQ(g.check(1e8, 13, x, u), StateGate::Verdict::RejectedTime);         // far ahead
  EXPECT_EQ(g.check(1.0 + 0.14, 12, x, u), StateGate::Verdict::RejectedTime);  // 1.4 periods for 2 numbers
  EXPECT_EQ(g.check(1.0 + 0.27, 13, x, u), StateGate::Verdict::Accepted);      // 2.7 periods for 3 (+-0.5 T)
  EXPECT_EQ(g.counts()[io::Reject::Time], 4);
}

TEST(StateGate, BeyondItsHorizonTheGateJudgesTimeOnlyAndResetStartsANewTrack) {
  const Integrator m;
  StateGate g = make_gate(m, 5);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  g.check(0.0, 1, x, u);
  x(0) = 1.5;  // after 10 periods of silence nothing is predicted
  EXPECT_EQ(g.check(10 * kT, 11, x, u), StateGate::Verdict::Accepted);
  g.reset();
  x(0) = -1.9;
  EXPECT_EQ(g.check(0.0, 1, x, u), StateGate::Verdict::First);
}

TEST(StateGate, TheYawWrapsAround) {
  StateGateSettings s;
  s.period = kT;
  s.jump = Eigen::VectorXd::Constant(1, 0.1);
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(1, 1), B = Eigen::MatrixXd::Zero(1, 1);
  StateGate g(A, B, Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1), {StateKind::Yaw}, s);
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(1);
  g.check(0.0, 1, Eigen::VectorXd::Constant(1, M_PI - 0.01), u);
  EXPECT_EQ(g.check(kT, 2, Eigen::VectorXd::Constant(1, -M_PI + 0.01), u), StateGate::Verdict::Accepted);
}

TEST(StateGate, DefaultThresholdsAreHalfTheWidestHalfWidthOfEachGroup) {
  LinkSettings l;
  l.jump_angle = 0.3;  // configured; the others default
  const std::vector<StateKind> kinds = {StateKind::Position, StateKind::Position, StateKind::Angle, StateKind::Yaw,
                                        StateKind::Velocity, StateKind::AngularRate, StateKind::AngularRate};
  const Eigen::VectorXd half = (Eigen::VectorXd(7) << 1.0, 2.0, 0.5, 0.5, 0.6, 2.0, 0.2).finished();
  const StateGateSettings s = state_gate_settings(l, kinds, half, 0.012);
  EXPECT_DOUBLE_EQ(s.jump(0), 1.0);
  EXPECT_DOUBLE_EQ(s.jump(1), 1.0);
  EXPECT_DOUBLE_EQ(s.jump(2), 0.3);
  EXPECT_DOUBLE_EQ(s.jump(3), 0.3);
  EXPECT_DOUBLE_EQ(s.jump(4), 0.3);
  EXPECT_DOUBLE_EQ(s.jump(5), 1.0);
  EXPECT_DOUBLE_EQ(s.jump(6), 1.0);
  const io::DecoderSettings d = state_decoder_settings(l, kinds);
  EXPECT_DOUBLE_EQ(d.bound[0], l.bound_position);
  EXPECT_DOUBLE_EQ(d.bound[2], l.bound_angle);
  EXPECT_DOUBLE_EQ(d.bound[3], l.bound_yaw);
  EXPECT_DOUBLE_EQ(d.bound[5], l.bound_rate);
}

TEST(StateGate, InconsistentSizesAreRefused) {
  const Integrator m;
  StateGateSettings s;
  s.period = kT;
  s.jump = Eigen::VectorXd::Constant(3, 0.1);  // three thresholds for two states
  EXPECT_THROW(StateGate(m.An(), m.Bn(), m.N_x, m.N_u, {StateKind::Position, StateKind::Velocity}, s),
               std::invalid_argument);
}

}  // namespace
}  // namespace tmpc
