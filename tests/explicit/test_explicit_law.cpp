// The explicit law of the case study (the config's explicit horizon and box): the
// affine laws equal the reference QP solution, every located point is feasible and
// every feasible point is located (an LP decides feasibility), the scan (1 and 2
// threads) and the tree agree, the companion file is strict.
#include <random>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/explicit/explicit_law.hpp"
#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/synthesis/record_file.hpp"

namespace tmpc {
namespace {

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

ExplicitOptions options() {
  const ExplicitSettings e = test::quick_config().explicit_mpc;
  ExplicitOptions o;
  o.N = e.horizon;
  o.M = e.control_horizon;
  // Under ASan half the config's box: CLP's work areas, allocated anew for each of the
  // enumeration's LPs, are large blocks that ASan maps and unmaps (59 % of the run in
  // the kernel's TLB flushes, perf); the config's law took 870 s of the asan variant.
  // The same code paths over fewer regions; the default build checks the config's.
  o.domain_fraction = test::kSanitized ? 0.5 * e.domain_fraction : e.domain_fraction;
  return o;
}

const ExplicitLaw& law() {
  static const ExplicitLaw l = build_explicit_law(artifact(), options());
  return l;
}

TEST(ExplicitLaw, CaseStudyPartitionIsCompleteAndMatchesTheReferenceAt100kPoints) {
  const ExplicitLaw& l = law();
  ASSERT_TRUE(l.stats.complete) << l.stats.stop_reason;
  // README: 399 regions (N = 2, M = 1, half of the tightened box); LP round-off may
  // move a degenerate region or two on another machine. Under ASan, a quarter of the
  // box (options()): 125 regions.
  EXPECT_NEAR(l.regions(), test::kSanitized ? 125 : 399, 4);
  EXPECT_EQ(l.stats.unresolved_facets, 0);
  const MpQp mp = explicit_mpqp(artifact(), options());
  auto ref = make_reference_solver(mp.as_parametric());
  const RegionScan scan1(l.table, 1), scan2(l.table, 2);
  std::mt19937_64 rng(11);
  Eigen::VectorXd th(l.n), z(l.nz);
  int located = 0, infeasible = 0;
  double worst = 0.0;
  const int samples = test::sample_count(100000);
  for (int k = 0; k < samples; ++k) {
    for (int j = 0; j < l.n; ++j) th(j) = std::uniform_real_distribution<double>(l.domain.lo(j), l.domain.hi(j))(rng);
    const int r1 = scan1.locate(th);
    ASSERT_EQ(scan2.locate(th), r1) << "sample " << k;
    ASSERT_EQ(l.tree.locate(l.table, th), r1) << "sample " << k;
    if (r1 < 0) {
      ASSERT_FALSE(mpqp_feasible(mp, th)) << "feasible sample " << k << " outside every region (a hole)";
      ++infeasible;
      continue;
    }
    ++located;
    const SolveResult& s = ref->solve(th);
    ASSERT_EQ(s.status, SolveStatus::Converged) << "sample " << k;
    l.evaluate(r1, th, z);
    worst = std::max(worst, (z - s.z).cwiseAbs().maxCoeff());
    ASSERT_LE((z - s.z).cwiseAbs().maxCoeff(), 1e-6) << "sample " << k << " region " << r1;
  }
  EXPECT_GT(located, samples / 10);
  EXPECT_GT(infeasible, 0);  // the box reaches outside the feasible set: those points say so
  std::printf("explicit law: %d regions, %d of %d samples located, max |z - z_ref| %.2e\n", l.regions(), located,
              samples, worst);
}

TEST(ExplicitLaw, SolverReportsInfeasibleOutsideThePartitionAndRefusesInvalidInput) {
  auto s = make_explicit_solver(artifact(), law());
  const Eigen::VectorXd center = law().domain.center();
  EXPECT_EQ(s->solve(center).status, SolveStatus::Converged);
  Eigen::VectorXd far = law().domain.hi + Eigen::VectorXd::Constant(law().n, 0.1);
  EXPECT_EQ(s->solve(far).status, SolveStatus::Infeasible);
  EXPECT_EQ(s->solve(Eigen::VectorXd::Constant(3, 0.0)).status, SolveStatus::InvalidInput);
  Eigen::VectorXd nan = center;
  nan(4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(s->solve(nan).status, SolveStatus::InvalidInput);
}

TEST(ExplicitLaw, SaysItDoesNotSolveTheInputRateWeightedForm) {
  // Its regions partition the nominal state only; the previous input would be m more
  // parameters (qp/mpc_qp.hpp): refused by name, not solved for another cost.
  ControllerArtifact rated = artifact();
  rated.Sigma_delta = 10.0 * rated.Sigma_lambda;
  try {
    explicit_mpqp(rated, options());
    ADD_FAILURE() << "explicit_mpqp accepted an input-rate-weighted design";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("weights.input_rate"), std::string::npos) << e.what();
  }
}

TEST(ExplicitLaw, CompanionFileRoundTripsAndRejectsCorruptionAndAnotherArtifact) {
  const std::vector<std::uint8_t> bytes = serialize_explicit(law());
  const ExplicitLaw back = deserialize_explicit(bytes, "mem");
  EXPECT_EQ(back.regions(), law().regions());
  EXPECT_EQ(back.table.H, law().table.H);
  EXPECT_EQ(back.Kz, law().Kz);
  EXPECT_EQ(back.tree.nodes.size(), law().tree.nodes.size());
  std::mt19937 rng(2);
  Eigen::VectorXd th(law().n);
  for (int k = 0; k < 1000; ++k) {
    for (int j = 0; j < law().n; ++j) th(j) = std::uniform_real_distribution<double>(law().domain.lo(j), law().domain.hi(j))(rng);
    ASSERT_EQ(back.tree.locate(back.table, th), law().tree.locate(law().table, th));
  }
  std::vector<std::uint8_t> bad = bytes;
  bad[bad.size() / 2] ^= 0x40;
  try {
    deserialize_explicit(bad, "bad.tmpcx");
    FAIL() << "a corrupt file was accepted";
  } catch (const RecordFileError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
  }
  const std::string path = ::testing::TempDir() + "law.tmpcx";
  save_explicit(law(), path);
  EXPECT_NO_THROW(load_explicit(path, &artifact()));
  ControllerArtifact other = artifact();
  other.margin += 1.0;
  try {
    load_explicit(path, &other);
    FAIL() << "a law of another artifact was accepted";
  } catch (const RecordFileError& e) {
    EXPECT_NE(std::string(e.what()).find("another controller artifact"), std::string::npos) << e.what();
  }
  // Semantics behind a valid checksum: a domain beyond the artifact's tightened set, a
  // domain fraction outside (0, 1], an empty domain.
  ExplicitLaw wide = law();
  wide.domain.hi(3) = artifact().x_bar.hi(3) * 2.0;
  save_explicit(wide, path);
  try {
    load_explicit(path, &artifact());
    FAIL() << "a domain outside x_bar was accepted";
  } catch (const RecordFileError& e) {
    EXPECT_NE(std::string(e.what()).find("record 'domain_lo': dimension 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("leaves the artifact's tightened state set"), std::string::npos) << e.what();
  }
  ExplicitLaw frac = law();
  frac.domain_fraction = 1.5;
  try {
    deserialize_explicit(serialize_explicit(frac), "f.tmpcx");
    FAIL() << "a domain fraction of 1.5 was accepted";
  } catch (const RecordFileError& e) {
    EXPECT_NE(std::string(e.what()).find("record 'domain_fraction' is 1.5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("must be in (0, 1]"), std::string::npos) << e.what();
  }
  ExplicitLaw empty = law();
  empty.domain.lo(0) = empty.domain.hi(0) + 1.0;
  try {
    deserialize_explicit(serialize_explicit(empty), "e.tmpcx");
    FAIL() << "an empty domain was accepted";
  } catch (const RecordFileError& e) {
    EXPECT_NE(std::string(e.what()).find("empty in dimension 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tmpc
