// Campaign statistics and Welch's t-test.
#include "tmpc/metrics/campaign.hpp"

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace tmpc {

namespace {

// Regularized incomplete beta I_x(a, b) by its continued fraction (modified Lentz),
// using the symmetry I_x(a, b) = 1 - I_(1-x)(b, a) where the fraction converges slowly.
double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - incomplete_beta(b, a, 1.0 - x);
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                                b * std::log1p(-x)) / a;
  const double tiny = 1e-300;
  double f = 1.0, c = 1.0, d = 0.0;
  for (int i = 0; i <= 400; ++i) {
    const int m = i / 2;
    double num;
    if (i == 0) {
      num = 1.0;
    } else if (i % 2 == 0) {
      num = m * (b - m) * x / ((a + 2.0 * m - 1.0) * (a + 2.0 * m));
    } else {
      num = -(a + m) * (a + b + m) * x / ((a + 2.0 * m) * (a + 2.0 * m + 1.0));
    }
    d = 1.0 + num * d;
    if (std::abs(d) < tiny) d = tiny;
    d = 1.0 / d;
    c = 1.0 + num / c;
    if (std::abs(c) < tiny) c = tiny;
    const double cd = c * d;
    f *= cd;
    if (std::abs(1.0 - cd) < 1e-15) break;
  }
  return front * (f - 1.0);
}

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double var_of(const std::vector<double>& v, double m) {
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return s / static_cast<double>(v.size() - 1);
}

}  // namespace

double student_t_two_sided_p(double t, double dof) {
  if (!(dof > 0.0) || !std::isfinite(t)) return std::isfinite(t) ? 1.0 : 0.0;
  return incomplete_beta(0.5 * dof, 0.5, dof / (dof + t * t));
}

WelchTest welch_t_test(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 2 || b.size() < 2) {
    throw std::invalid_argument("Welch t-test: each sample needs at least 2 values (got " + std::to_string(a.size()) +
                                " and " + std::to_string(b.size()) + ")");
  }
  WelchTest w;
  w.mean_a = mean_of(a);
  w.mean_b = mean_of(b);
  const double va = var_of(a, w.mean_a) / static_cast<double>(a.size());
  const double vb = var_of(b, w.mean_b) / static_cast<double>(b.size());
  if (va + vb <= 0.0) {
    w.t = w.mean_a == w.mean_b ? 0.0 : std::copysign(INFINITY, w.mean_a - w.mean_b);
    w.dof = static_cast<double>(a.size() + b.size() - 2);
    w.p = w.mean_a == w.mean_b ? 1.0 : 0.0;
    return w;
  }
  w.t = (w.mean_a - w.mean_b) / std::sqrt(va + vb);
  w.dof = (va + vb) * (va + vb) /
          (va * va / static_cast<double>(a.size() - 1) + vb * vb / static_cast<double>(b.size() - 1));
  w.p = student_t_two_sided_p(w.t, w.dof);
  return w;
}

std::string campaign_json(const std::vector<MissionMetrics>& runs, unsigned seed) {
  nlohmann::json j;
  j["monte_carlo"] = {{"runs", runs.size()}, {"seed", seed}};
  nlohmann::json list = nlohmann::json::array();
  for (const MissionMetrics& m : runs) list.push_back(nlohmann::json::parse(metrics_json(m)));
  // Mean and standard deviation of every numeric leaf of the per-run objects.
  nlohmann::json mean = list.empty() ? nlohmann::json::object() : list.front(), sd = mean;
  const auto flat = mean.flatten();
  nlohmann::json fm = flat, fs = flat;
  for (auto it = flat.begin(); it != flat.end(); ++it) {
    if (!it.value().is_number()) continue;
    std::vector<double> v;
    for (const auto& r : list) v.push_back(r.flatten()[it.key()].get<double>());
    const double m = mean_of(v);
    fm[it.key()] = m;
    fs[it.key()] = v.size() > 1 ? std::sqrt(var_of(v, m)) : 0.0;
  }
  j["mean"] = fm.unflatten();
  j["std"] = fs.unflatten();
  j["runs"] = list;
  return j.dump(2);
}

}  // namespace tmpc
