// Campaign statistics: Student's t tail against its closed forms (1 and 2 degrees of
// freedom) and table values, Welch's statistic and degrees of freedom by hand, the
// campaign mean and standard deviation.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tmpc/metrics/campaign.hpp"

namespace tmpc {
namespace {

TEST(Campaign, StudentTTailMatchesClosedFormsAndTables) {
  for (double t : {0.0, 0.3, 1.0, 2.5, 10.0, 100.0}) {
    EXPECT_NEAR(student_t_two_sided_p(t, 1.0), 1.0 - 2.0 * std::atan(t) / M_PI, 1e-12) << t;  // Cauchy
    EXPECT_NEAR(student_t_two_sided_p(t, 2.0), 1.0 - t / std::sqrt(2.0 + t * t), 1e-12) << t;
    EXPECT_NEAR(student_t_two_sided_p(-t, 2.0), student_t_two_sided_p(t, 2.0), 1e-15);
  }
  EXPECT_NEAR(student_t_two_sided_p(2.228, 10.0), 0.05, 2e-4);  // t tables, 5 % two-sided
  EXPECT_NEAR(student_t_two_sided_p(2.042, 30.0), 0.05, 2e-4);
  EXPECT_NEAR(student_t_two_sided_p(1.95996, 1e7), 0.05, 1e-5);  // the normal limit
  EXPECT_NEAR(student_t_two_sided_p(4.032, 5.0), 0.01, 1e-4);
}

TEST(Campaign, WelchStatisticAndDegreesOfFreedom) {
  const WelchTest w = welch_t_test({1, 2, 3, 4, 5}, {2, 4, 6, 8, 10});
  // var a = 2.5, var b = 10; se^2 = 0.5 + 2 = 2.5; dof = 2.5^2 / (0.5^2/4 + 2^2/4).
  EXPECT_NEAR(w.t, -3.0 / std::sqrt(2.5), 1e-12);
  EXPECT_NEAR(w.dof, 6.25 / (0.0625 + 1.0), 1e-12);
  EXPECT_GT(w.p, 0.05);
  EXPECT_LT(w.p, 0.2);
  EXPECT_NEAR(welch_t_test({1, 1, 1}, {1, 1, 1}).p, 1.0, 0.0);
  EXPECT_THROW(welch_t_test({1.0}, {1.0, 2.0}), std::invalid_argument);
}

TEST(Campaign, JsonHoldsMeanStdAndEveryRun) {
  MissionMetrics a, b;
  a.state_names = b.state_names = {"x", "y"};
  a.rmse = {1.0, 0.5};
  b.rmse = {3.0, 0.5};
  a.fallback_periods = 2;
  b.fallback_periods = 4;
  const nlohmann::json j = nlohmann::json::parse(campaign_json({a, b}, 7));
  EXPECT_EQ(j["monte_carlo"]["runs"], 2);
  EXPECT_EQ(j["monte_carlo"]["seed"], 7);
  EXPECT_DOUBLE_EQ(j["mean"]["rmse"]["x"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(j["std"]["rmse"]["x"].get<double>(), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(j["mean"]["fallback_periods"].get<double>(), 3.0);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["runs"][1]["rmse"]["x"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["std"]["rmse"]["y"].get<double>(), 0.0);
}

}  // namespace
}  // namespace tmpc
