// The softened QP's penalty from sampled multipliers (see soft_penalty.hpp).
#include "tmpc/solvers/soft_penalty.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "tmpc/solvers/solver.hpp"

namespace tmpc {

SoftPenaltyCalibration calibrate_soft_penalty(const ControllerArtifact& a, double safety, int directions,
                                              unsigned seed) {
  const MpcQpData d = a.qp(a.tube_law.offset_free);
  SolverOptions o;
  o.warm_start = false;
  o.eps_abs = o.eps_rel = 1e-6;
  auto admm = make_solver("admm", d, o);       // feasibility (a certified infeasibility in a few iterations)
  auto exact = make_solver("reference", d, o);  // multipliers (KKT below 1e-9)
  const int np = d.parameters(), nz = d.variables();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(np), dir(d.n);
  auto at = [&](double t) -> Eigen::VectorXd& {
    theta.head(d.n) = t * dir;
    return theta;
  };
  auto feasible = [&](double t) { return admm->solve(at(t)).status == SolveStatus::Converged; };
  SoftPenaltyCalibration c;
  for (int k = 0; k < directions; ++k) {
    for (int i = 0; i < d.n; ++i) dir(i) = normal(rng);
    dir /= dir.cwiseAbs().maxCoeff();  // a ray in the normalized state box
    double lo = 0.0, hi = 1.0;
    while (feasible(hi) && hi < 1e3) {
      lo = hi;
      hi *= 2.0;
    }
    for (int it = 0; it < 14; ++it) {
      const double mid = 0.5 * (lo + hi);
      (feasible(mid) ? lo : hi) = mid;
    }
    for (double frac : {0.1, 0.2, 0.3}) {
      const SolveResult& r = exact->solve(at(frac * lo));
      if (r.status != SolveStatus::Converged) continue;
      ++c.samples;
      int worst = -1;
      const double sum = largest_multiplier_sum(r.y, nz, d.N, d.n, &worst);
      if (sum > c.largest_multiplier_sum) {
        c.largest_multiplier_sum = sum;
        c.worst_state = worst;
      }
    }
  }
  c.penalty = std::max(1.0, safety * c.largest_multiplier_sum);
  return c;
}

double largest_multiplier_sum(const Eigen::VectorXd& y, int first, int N, int n, int* worst) {
  double largest = 0.0;
  for (int i = 0; i < n; ++i) {
    double sum = 0.0;
    for (int k = 0; k < N; ++k) sum += std::abs(y(first + k * n + i));
    if (sum > largest) {
      largest = sum;
      if (worst != nullptr) *worst = i;
    }
  }
  return largest;
}

SoftPenaltyCalibration apply_soft_penalty(ControllerArtifact& a, double safety) {
  if (!a.soft_constraints || a.soft_penalty > 0.0) return {};
  const SoftPenaltyCalibration c = calibrate_soft_penalty(a, safety);
  a.soft_penalty = c.penalty;
  return c;
}

}  // namespace tmpc
