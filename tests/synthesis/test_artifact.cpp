// Controller artifact: bit-exact round trip, every corruption class rejected with
// its message, and a fuzz of single-byte mutations and truncations.
#include <random>

#include <gtest/gtest.h>

#include "design_fixture.hpp"

namespace tmpc {
namespace {

const std::vector<std::uint8_t>& bytes() {
  static const std::vector<std::uint8_t> b = serialize_artifact(test::quick_artifact());
  return b;
}

std::string error_of(const std::vector<std::uint8_t>& b) {
  try {
    deserialize_artifact(b, "t.tmpc");
  } catch (const ArtifactError& e) {
    return e.what();
  }
  return "";
}

void fix_crc(std::vector<std::uint8_t>& b) {
  const std::uint32_t c = crc32(b.data(), b.size() - 4);
  for (int i = 0; i < 4; ++i) b[b.size() - 4 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(c >> (8 * i));
}

TEST(Artifact, RoundTripIsBitExact) {
  const ControllerArtifact a = deserialize_artifact(bytes(), "t.tmpc");
  EXPECT_EQ(serialize_artifact(a), bytes());
  const ControllerArtifact& ref = test::quick_artifact();
  EXPECT_EQ(a.K, ref.K);
  EXPECT_EQ(a.Z.G, ref.Z.G);
  EXPECT_EQ(a.config_text, ref.config_text);
  // The QP data rebuilt from the artifact equals the design's.
  EXPECT_EQ(a.qp().H, test::quick_design().qp.H);
}

TEST(Artifact, EveryCorruptionClassIsRejectedWithItsMessage) {
  std::vector<std::uint8_t> b = bytes();
  b[0] = 'X';
  EXPECT_NE(error_of(b).find("bad magic"), std::string::npos);
  b = bytes();
  b[8] = 9;
  fix_crc(b);
  EXPECT_NE(error_of(b).find("format version 9"), std::string::npos) << error_of(b);
  b = bytes();
  b.resize(b.size() - 100);
  EXPECT_NE(error_of(b).find("truncated or extended"), std::string::npos);
  b = bytes();
  b.push_back(0);
  EXPECT_NE(error_of(b).find("truncated or extended"), std::string::npos);
  b = bytes();
  b[b.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(b).find("checksum mismatch"), std::string::npos);
  // A dimension mismatch behind a valid checksum: K stored as 4 x 23.
  ControllerArtifact a = deserialize_artifact(bytes(), "t.tmpc");
  a.K = a.K.leftCols(23).eval();
  b = serialize_artifact(a);
  EXPECT_NE(error_of(b).find("record 'K' is 4x23, expected 4x24"), std::string::npos) << error_of(b);
  EXPECT_NE(error_of({1, 2, 3}).find("truncated"), std::string::npos);
  EXPECT_THROW(load_artifact("/nonexistent/controller.tmpc"), ArtifactError);
}

TEST(Artifact, FuzzedMutationsAndTruncationsAreNeverAccepted) {
  std::mt19937_64 rng(77);
  const std::vector<std::uint8_t>& good = bytes();
  std::uniform_int_distribution<std::size_t> pos(0, good.size() - 1);
  std::uniform_int_distribution<int> val(1, 255);
  int rejected = 0;
  for (int k = 0; k < 1000; ++k) {
    std::vector<std::uint8_t> b = good;
    b[pos(rng)] ^= static_cast<std::uint8_t>(val(rng));  // a real change of one byte
    rejected += !error_of(b).empty();
  }
  for (int k = 0; k < 300; ++k) {
    std::vector<std::uint8_t> b(good.begin(), good.begin() + static_cast<long>(pos(rng)));
    rejected += !error_of(b).empty();
  }
  EXPECT_EQ(rejected, 1300);
}


}  // namespace
}  // namespace tmpc

namespace tmpc {
namespace {

/// The message of loading `a` (serialized with a valid checksum), "" when it loads.
std::string semantic_error(const ControllerArtifact& a) { return error_of(serialize_artifact(a)); }

ControllerArtifact good() { return deserialize_artifact(bytes(), "t.tmpc"); }

void expect_refused(const ControllerArtifact& a, const std::string& record, const std::string& what) {
  const std::string m = semantic_error(a);
  EXPECT_NE(m.find("t.tmpc"), std::string::npos) << m;
  EXPECT_NE(m.find("record '" + record + "'"), std::string::npos) << "record '" << record << "' not named in: " << m;
  EXPECT_NE(m.find(what), std::string::npos) << "'" << what << "' not in: " << m;
}

TEST(ArtifactSemantics, AFreshDesignPassesEveryCheck) { EXPECT_EQ(semantic_error(good()), ""); }

/// check_artifact() on the records in memory (no serialization): "" when they pass.
std::string check_error(const ControllerArtifact& a) {
  try {
    check_artifact(a, "t.tmpc");
  } catch (const ArtifactError& e) {
    return e.what();
  }
  return "";
}

TEST(ArtifactSemantics, DimensionsTheRuntimeDoesNotSupportAreRefused) {
  ControllerArtifact a = good();
  a.n = 30;  // the records stay 24-dimensional: the loader's shape check names one
  const std::string m = semantic_error(a);
  EXPECT_NE(m.find("t.tmpc: record '"), std::string::npos) << m;
  EXPECT_NE(m.find("expected"), std::string::npos) << m;
  a = good();
  a.n = 60;
  EXPECT_NE(check_error(a).find("record 'n': is 60, must be in [1, 48]"), std::string::npos) << check_error(a);
  a = good();
  a.m = 17;
  EXPECT_NE(check_error(a).find("record 'm': is 17, must be in [1, 16]"), std::string::npos) << check_error(a);
  a = good();
  a.measured = 19;  // a tiltrotor measures 20 states
  EXPECT_NE(check_error(a).find("the tiltrotor has 24, 20 and 4"), std::string::npos) << check_error(a);
  a = good();
  std::swap(a.kinds[0], a.kinds[3]);  // a position where an angle was
  EXPECT_NE(check_error(a).find("are not the tiltrotor's"), std::string::npos) << check_error(a);
  a = good();
  a.kinds[2] = StateKind::Integral;
  EXPECT_NE(check_error(a).find("integral states come after the 20 measured ones"), std::string::npos)
      << check_error(a);
}

// The law's reversion bounds (tube_law.revert_beyond, revert_within): 0 or above 1, the
// leave bound in [1, the enter bound], and as the embedded configuration says.
TEST(ArtifactSemantics, TheReversionBoundsAreChecked) {
  ControllerArtifact a = good();
  ASSERT_DOUBLE_EQ(a.tube_law.revert_beyond, 4.0);
  a.tube_law.revert_beyond = 0.5;
  expect_refused(a, "tube_law_revert", "neither 0 (off) nor above 1");
  a = good();
  a.tube_law.revert_within = 6.0;
  expect_refused(a, "tube_law_revert", "not in [1, the enter bound]");
  a = good();
  a.tube_law.revert_beyond = 0.0;  // valid, but not what the embedded configuration says
  expect_refused(a, "tube_law_revert", "tube_law.revert_beyond");
}

TEST(ArtifactSemantics, GainsThatDoNotStabilizeAreRefused) {
  ControllerArtifact a = good();
  a.K *= 100.0;
  expect_refused(a, "K", "does not stabilize the nominal model");
  a = good();
  a.K = -a.K;
  expect_refused(a, "K", "spectral radius");
  a = good();
  a.K_lqr *= -1.0;
  expect_refused(a, "K_lqr", "does not stabilize");
}

TEST(ArtifactSemantics, ScalingsSetsAndCostAreChecked) {
  ControllerArtifact a = good();
  a.N_x(3) = -2.0;
  expect_refused(a, "N_x", "entry 3 is -2, a scaling must be positive");
  a = good();
  a.N_u(0) = 0.0;
  expect_refused(a, "N_u", "must be positive");
  a = good();
  a.x_bar.lo(5) = a.x_bar.hi(5) + 0.1;
  expect_refused(a, "x_bar_lo", "empty in dimension 5");
  a = good();
  a.u_bar.hi = a.U.hi * 2.0;
  expect_refused(a, "u_bar_lo", "not inside U");
  a = good();
  a.Sigma_lambda = -a.Sigma_lambda;
  expect_refused(a, "Sigma_lambda", "positive definite");
  a = good();
  a.Sigma_rho(0, 1) = 5.0;  // not symmetric
  expect_refused(a, "Sigma_rho", "not symmetric");
  a = good();
  a.margin = 0.5;
  expect_refused(a, "margin", "margin >= 1");
  a = good();
  a.envelope.yaw_rate_max = 20.0;
  expect_refused(a, "envelope_numbers", "above 10 rad/s");
  a = good();
  a.envelope.yaw_rate_max = 0.5;  // not the embedded configuration's 0.2
  expect_refused(a, "envelope_numbers", "envelope.yaw_rate_max");
}

TEST(ArtifactSemantics, RecordsMustAgreeWithTheEmbeddedConfiguration) {
  ControllerArtifact a = good();
  a.sample_time = 0.024;
  expect_refused(a, "sample_time", "is 0.024, the embedded configuration gives 0.012");
  a.sample_time = 1e300;
  expect_refused(a, "sample_time", "must be in [1e-5, 1] s");
  a = good();
  a.tube_gain = "lmi_thesis";
  expect_refused(a, "tube_gain", "synthesis.tube_gain is 'lqr'");
  a = good();
  a.M = 2;
  expect_refused(a, "M", "synthesis.control_horizon is 4");
  // The vehicle edited after the design: the body mass x 1.5 still configures a vehicle
  // that can hover, but not the one the records were designed for; likewise the
  // vehicle record edited (the runtime's feedforward uses it, not the YAML).
  a = good();
  const std::string from = "mass: 1.7068";
  a.config_text.replace(a.config_text.find(from), from.size(), "mass: 2.5602");
  expect_refused(a, "vehicle_scalars", "the embedded configuration gives 2.5602");
  a = good();
  a.vehicle.body_mass *= 1.5;
  expect_refused(a, "vehicle_scalars", "is 2.5602, the embedded configuration gives 1.7068");
  a = good();
  a.u_eq(0) += 0.5;
  expect_refused(a, "u_eq", "the hover input of the embedded vehicle");
  // x 10 cannot hover within the thrust limits: the embedded configuration is invalid.
  a = good();
  a.config_text.replace(a.config_text.find(from), from.size(), "mass: 17.068");
  expect_refused(a, "config", "constraints.input_max[0]");
  a = good();
  a.config_text = "vehicle: [unclosed";
  expect_refused(a, "config", "YAML syntax error");
}

TEST(ArtifactSemantics, AHugeHorizonIsRefusedBeforeAnythingIsBuilt) {
  ControllerArtifact a = good();
  a.N = 19220;
  const std::string m = semantic_error(a);
  EXPECT_NE(m.find("record 'N' = 19220 out of range [1, 200]"), std::string::npos) << m;
}

TEST(ArtifactSemantics, SpecialFilesAreClearErrors) {
  for (const char* path : {"/dev/zero", "/tmp"}) {
    try {
      load_artifact(path);
      FAIL() << path;
    } catch (const ArtifactError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}


// The noisy-sensor design's records: the Kalman filter and the soft constraints'
// penalty round-trip, and what they must mean is checked on load.
TEST(ArtifactSemantics, TheRedundantRowCertificateRoundTripsAndIsChecked) {
  const ControllerArtifact a0 = good();
  ASSERT_GE(a0.redundant_rows.size(), 2u);
  EXPECT_EQ(deserialize_artifact(serialize_artifact(a0), "t.tmpc").redundant_rows, a0.redundant_rows);
  ControllerArtifact a = a0;
  std::swap(a.redundant_rows[0], a.redundant_rows[1]);
  expect_refused(a, "redundant_rows", "is not an increasing index of a QP row");
  a = a0;
  a.redundant_rows_offset_free.push_back(a.M * a.m + a.N * a.n);  // one past the last row
  expect_refused(a, "redundant_rows_offset_free", "is not an increasing index of a QP row");
  a = a0;
  a.certificate_d_max(0) = -1.0;
  expect_refused(a, "certificate_d_max", "negative");
}

TEST(ArtifactSemantics, TheKalmanFilterAndTheSoftPenaltyRoundTripAndAreChecked) {
  const ControllerArtifact& n = test::noisy_artifact();
  ASSERT_EQ(n.estimator, "kalman");
  ASSERT_GT(n.soft_penalty, 0.0);
  const ControllerArtifact back = deserialize_artifact(serialize_artifact(n), "t.tmpc");
  EXPECT_EQ(back.estimator_rows, n.estimator_rows);
  EXPECT_EQ(back.estimator_L, n.estimator_L);
  EXPECT_EQ(back.estimator_E_c, n.estimator_E_c);
  EXPECT_EQ(back.soft_penalty, n.soft_penalty);
  EXPECT_EQ(back.noise_margin, n.noise_margin);
  EXPECT_EQ(back.estimator_rows.size(), 20u);  // every physical state measured
  EXPECT_EQ(back.estimator_E_c.cols(), 7);     // the angular-rate rows
  EXPECT_EQ(check_error(back), "");
  ControllerArtifact a = back;
  a.estimator_L *= 40.0;  // a gain whose estimation error diverges
  EXPECT_NE(check_error(a).find("record 'estimator_L': the estimation error does not converge"), std::string::npos) << check_error(a);
  // The filter's covariances and start prior: P must be the DARE's for Q and give L.
  EXPECT_EQ(back.estimator_P, n.estimator_P);
  EXPECT_EQ(back.estimator_Q, n.estimator_Q);
  EXPECT_EQ(back.estimator_start, n.estimator_start);
  EXPECT_TRUE(back.filter_start_scheduled());  // tiltrotor.yaml's start_prior
  a = back;
  a.estimator_P *= 1.5;
  EXPECT_NE(check_error(a).find("record 'estimator_P': its gain"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_Q *= 2.0;
  EXPECT_NE(check_error(a).find("record 'estimator_P': is not a fixed point"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_Q(0, 1) = 1.0;
  EXPECT_NE(check_error(a).find("record 'estimator_Q': is not symmetric"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_start(0) = -1.0;
  EXPECT_NE(check_error(a).find("record 'estimator_start'"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_start(2) = 0.7;  // not what the embedded configuration gives
  EXPECT_NE(check_error(a).find("estimation.start_prior.state"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_rows[3] = a.estimator_rows[2];
  EXPECT_NE(check_error(a).find("record 'estimator_rows'"), std::string::npos) << check_error(a);
  a = back;
  a.Sigma_delta = -Eigen::MatrixXd::Identity(4, 4);
  EXPECT_NE(check_error(a).find("record 'Sigma_delta'"), std::string::npos) << check_error(a);
  // Found by the artifact fuzzer: a weight whose negative eigenvalue is within the cost
  // check's absolute tolerance (1e-9) but not the QP builder's, relative to the weight's
  // size. It escaped the loader as std::invalid_argument; the loader now builds the QP in
  // every form the runtime builds it and refuses the artifact with the builder's message.
  a = back;
  a.Sigma_delta = 1e-4 * Eigen::MatrixXd::Identity(4, 4);
  a.Sigma_delta(3, 3) = -1e-10;
  EXPECT_NE(check_error(a).find("t.tmpc: the QP cannot be built from the records: add_input_rate_weight: Sigma_delta is "
                                "not positive semidefinite"),
            std::string::npos)
      << check_error(a);
  a = back;
  ASSERT_TRUE(back.rate_weighted());  // the noisy design's weights.input_rate
  EXPECT_EQ(back.Sigma_delta, n.Sigma_delta);
  a.Sigma_delta *= 2.0;  // not what the embedded configuration gives
  EXPECT_NE(check_error(a).find("record 'Sigma_delta': is "), std::string::npos) << check_error(a);
  EXPECT_NE(check_error(a).find("weights.input_rate[0]"), std::string::npos) << check_error(a);
  a = back;
  a.soft_penalty = 0.0;
  EXPECT_NE(check_error(a).find("record 'soft_penalty': is 0 with soft constraints on"), std::string::npos) << check_error(a);
  a = back;
  a.estimator = "residual";  // the embedded configuration says kalman
  EXPECT_NE(check_error(a).find("record 'estimator'"), std::string::npos) << check_error(a);
  a = back;
  a.tube_law.offset_free = false;
  EXPECT_NE(check_error(a).find("record 'estimator': kalman estimates the offset-free law's disturbance"), std::string::npos)
      << check_error(a);
  // The filter's noise levels and the noise monitor (the switched observer).
  EXPECT_EQ(back.estimator_noise, n.estimator_noise);
  EXPECT_FALSE(back.switched_observer());  // tiltrotor_noisy.yaml has no noise_monitor
  EXPECT_NEAR(back.estimator_noise(0), 0.005 * back.N_x(0), 1e-12);  // measurement_noise.position, normalized
  a = back;
  a.estimator_noise(2) = -1.0;
  EXPECT_NE(check_error(a).find("record 'estimator_noise'"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_monitor << 0.05, 0.01, 1.0;
  EXPECT_NE(check_error(a).find("record 'estimator_monitor'"), std::string::npos) << check_error(a);
  a = back;
  a.estimator_monitor << 0.02, 0.05, 1.0;  // valid, but not what the embedded configuration gives
  EXPECT_NE(check_error(a).find("estimation.noise_monitor.residual_below"), std::string::npos) << check_error(a);
  const ControllerArtifact& s = test::quick_artifact();
  const ControllerArtifact sb = deserialize_artifact(serialize_artifact(s), "s.tmpc");
  EXPECT_TRUE(sb.switched_observer());
  EXPECT_EQ(sb.estimator_monitor, Eigen::Vector3d(0.025, 0.05, 1.0));
}

}  // namespace
}  // namespace tmpc
