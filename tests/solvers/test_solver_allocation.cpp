// solve() allocates nothing: a counting global operator new over repeated solves.
#include <string>

#include <gtest/gtest.h>

#include "../allocation_counter.hpp"
#include "../synthesis/design_fixture.hpp"
#include "tmpc/explicit/explicit_solver.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {
namespace {

using test::g_allocations;

TEST(SolverAllocation, SolveAllocatesNothing) {
  test::g_count_all = true;  // every thread counts
  const ControllerArtifact a = test::quick_artifact();
  Eigen::VectorXd x0 = Eigen::VectorXd::Constant(24, 0.01);
  for (const char* name : {"admm", "admm-crash", "admm-thesis", "cz", "reference", "active-set"}) {
    SolverOptions o;
    o.max_iterations = 300;
    const bool crash = std::string(name) == "admm-crash";  // the active-set crash start
    o.crash_start = crash;
    auto s = make_solver(crash ? "admm" : name, a, o);
    s->solve(x0);  // warm-up
    const long before = g_allocations.load();
    for (int k = 0; k < 20; ++k) {
      x0(0) = 0.01 + 1e-4 * k;
      s->solve(x0);
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << name << " allocated in solve()";
  }
}

TEST(SolverAllocation, ExplicitSolveAllocatesNothing) {
  test::g_count_all = true;  // the scan's OpenMP workers count too
  const ControllerArtifact a = test::quick_artifact();
  ExplicitOptions o;  // a small law is enough: the online path is the same
  o.N = 1;
  o.M = 1;
  o.domain_fraction = 0.2;
  for (Locator loc : {Locator::Tree, Locator::Scan}) {
    auto s = make_explicit_solver(a, build_explicit_law(a, o), loc, loc == Locator::Scan ? 2 : 1);
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(24);
    ASSERT_EQ(s->solve(x0).status, SolveStatus::Converged);  // warm-up (OpenMP's thread pool)
    const long before = g_allocations.load();
    for (int k = 0; k < 20; ++k) {
      x0(0) = 1e-3 * k;
      s->solve(x0);
    }
    EXPECT_EQ(g_allocations.load() - before, 0) << "explicit solve allocated";
  }
}

}  // namespace
}  // namespace tmpc
