// Monte Carlo campaigns and their comparison (thesis 6.5, Table 6.1's metrics):
// per-run mission metrics, their mean and standard deviation, and Welch's t-test of
// two campaigns' per-run values (unequal variances, Welch-Satterthwaite degrees of
// freedom, two-sided p from the Student t distribution).
#pragma once

#include <string>
#include <vector>

#include "tmpc/metrics/mission.hpp"

namespace tmpc {

struct WelchTest {
  double mean_a = 0, mean_b = 0, t = 0, dof = 0, p = 1;
};

/// Welch's t-test of samples a and b (each with at least 2 values; throws otherwise).
WelchTest welch_t_test(const std::vector<double>& a, const std::vector<double>& b);

/// Two-sided tail probability P(|T| >= |t|) of Student's t with dof degrees of freedom.
double student_t_two_sided_p(double t, double dof);

/// metrics.json of a campaign: {"monte_carlo": {runs, seed}, "mean": {...}, "std": {...},
/// "runs": [ per-run metrics ]}; the per-run objects have the keys of metrics_json.
std::string campaign_json(const std::vector<MissionMetrics>& runs, unsigned seed);

}  // namespace tmpc
