// Parity bookkeeping of a GPU solve (or its kernel code on the host) against the
// CPU twin: status, u_bar(0) relative to the input range, iterations, and the KKT
// residuals of the float solution evaluated in double.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "tmpc/gpu/admm_problem.hpp"
#include "tmpc/solvers/kkt.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc::test {

struct ParityStats {
  int n = 0, status_mismatch = 0, iteration_outliers = 0, iteration_mismatches = 0, max_iteration_difference = 0;
  double worst_u = 0.0, iters_cpu = 0.0, iters_gpu = 0.0, worst_prim = 0.0, worst_stat = 0.0;

  /// One instance: the CPU result c, the GPU's status, iterations, z and (exact
  /// variant, else nullptr) multipliers y.
  void add(const QpSolver& cpu, const SolveResult& c, const Eigen::VectorXd& x0, const Eigen::VectorXd& u_range,
           int status, int iterations, const Eigen::VectorXd& z, const Eigen::VectorXd* y, int check_every) {
    ++n;
    if (status != static_cast<int>(c.status)) ++status_mismatch;
    const Eigen::Index m = u_range.size();
    worst_u = std::max(worst_u, ((z.head(m) - c.z.head(m)).cwiseQuotient(u_range)).cwiseAbs().maxCoeff());
    iters_cpu += c.iterations;
    iters_gpu += iterations;
    // Iteration counts of the exact variant are multiples of the check interval: one
    // interval is the resolution of the comparison.
    const int slack = std::max(static_cast<int>(std::ceil(0.1 * c.iterations)), check_every);
    iteration_mismatches += iterations != c.iterations;
    max_iteration_difference = std::max(max_iteration_difference, std::abs(iterations - c.iterations));
    if (std::abs(iterations - c.iterations) > slack) ++iteration_outliers;
    if (y != nullptr) {
      const CondensedQp qp = cpu.problem().instance(x0);
      const KktResiduals r = kkt_residuals(qp, z, *y);
      const double scale = std::max({(qp.H * z).cwiseAbs().maxCoeff(), qp.f.cwiseAbs().maxCoeff(), 1.0});
      worst_prim = std::max(worst_prim, r.primal);
      worst_stat = std::max(worst_stat, r.stationarity / scale);
    }
  }
  /// Means over the instances, and a line for the log.
  void finish(const char* what) {
    iters_cpu /= std::max(n, 1);
    iters_gpu /= std::max(n, 1);
    std::printf("%s: %d QPs, status mismatches %d, worst |du|/range %.2e, mean iterations cpu %.1f gpu %.1f, "
                "%d with other counts (at most %d apart), outliers %d, worst primal %.2e, rel. stationarity %.2e\n",
                what, n, status_mismatch, worst_u, iters_cpu, iters_gpu, iteration_mismatches, max_iteration_difference,
                iteration_outliers, worst_prim, worst_stat);
  }
};

/// The GPU issue's parity criteria: same status, |u_gpu - u_cpu| <= 1e-3 of the input
/// range, iterations within 10 % (mean; a few instances may move by more).
inline void expect_parity(const ParityStats& st, bool iterations = true) {
  EXPECT_EQ(st.status_mismatch, 0);
  EXPECT_LE(st.worst_u, 1e-3);
  if (!iterations) return;
  EXPECT_NEAR(st.iters_gpu, st.iters_cpu, 0.1 * st.iters_cpu);
  EXPECT_LE(st.iteration_outliers, st.n / 20);
}

/// What the README states for the exact variant's kernel code in float against its
/// double CPU twin: u(0) within 4e-6 of the input range, the same iteration count on
/// all but `mismatches` QPs, none more than one check interval (5) apart.
inline void expect_exact_twin(const ParityStats& st, int mismatches) {
  EXPECT_EQ(st.status_mismatch, 0);
  EXPECT_LE(st.worst_u, 4e-6);
  EXPECT_LE(st.iteration_mismatches, mismatches);
  EXPECT_LE(st.max_iteration_difference, 5);
}

}  // namespace tmpc::test
