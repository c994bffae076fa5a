// The optimizer thread of the real-time loop, without timing assumptions: a solver
// that waits behind a gate the test opens stands for a solve still running at the
// deadline. A late solve is abandoned (its result never used), no second solve
// starts while one is in flight, those periods take the LQR fallback, and a solve
// that finished is used. (The deadline rule itself, on a clock, is tested on a virtual
// clock in test_controller_loop.cpp.)
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>

#include "../synthesis/design_fixture.hpp"
#include "tmpc/runtime/async_optimizer.hpp"
#include "tmpc/runtime/tube_controller.hpp"

namespace tmpc {
namespace {

using namespace std::chrono_literals;

/// A real solver that, while the gate is closed, waits in solve() until it opens.
class GatedSolver final : public QpSolver {
 public:
  explicit GatedSolver(std::unique_ptr<QpSolver> inner) : inner_(std::move(inner)) {}
  const SolveResult& solve(const Eigen::VectorXd& x0) override {
    std::unique_lock<std::mutex> lock(m_);
    ++entered_;
    cv_.notify_all();
    cv_.wait(lock, [&] { return open_; });
    lock.unlock();
    return inner_->solve(x0);
  }
  void reset() override { inner_->reset(); }
  const char* name() const override { return "gated"; }
  const ParametricQp& problem() const override { return inner_->problem(); }
  const SolverOptions& options() const override { return inner_->options(); }
  void set_open(bool open) {
    std::lock_guard<std::mutex> lock(m_);
    open_ = open;
    cv_.notify_all();
  }
  /// Waits until `n` solves have entered (the worker is inside the solve).
  void wait_entered(int n) {
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait_for(lock, 10s, [&] { return entered_ >= n; });
  }

 private:
  std::unique_ptr<QpSolver> inner_;
  std::mutex m_;
  std::condition_variable cv_;
  bool open_ = true;
  int entered_ = 0;
};

const ControllerArtifact& artifact() {
  static const ControllerArtifact a = test::quick_artifact();
  return a;
}

/// Polls until the result of `ticket` is there (at most 10 s: a bound, not a timing).
const SolveResult* wait_for(const AsyncOptimizer& o, std::uint64_t ticket) {
  const auto end = std::chrono::steady_clock::now() + 10s;
  while (std::chrono::steady_clock::now() < end) {
    if (const SolveResult* r = o.poll(ticket)) return r;
    std::this_thread::sleep_for(100us);
  }
  return nullptr;
}

TEST(AsyncOptimizer, ResultEqualsTheSynchronousSolve) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(24, 0.01);
  SolverOptions o;
  o.warm_start = false;
  AsyncOptimizer async(make_solver("reference", artifact(), o), 24);
  auto sync = make_solver("reference", artifact(), o);
  const std::uint64_t t = async.start(x0);
  ASSERT_GT(t, 0u);
  const SolveResult* r = wait_for(async, t);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->status, SolveStatus::Converged);
  EXPECT_LE((r->z - sync->solve(x0).z).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(async.busy());
  EXPECT_EQ(async.start(Eigen::VectorXd::Zero(3)), 0u);  // wrong size: refused, not a crash
}

TEST(AsyncOptimizer, ALateSolveIsAbandonedAndBlocksASecondOne) {
  auto gated = std::make_unique<GatedSolver>(make_solver("admm", artifact()));
  GatedSolver* gate = gated.get();
  AsyncOptimizer async(std::move(gated), 24);  // the constructor's own sizing solve passes the open gate
  gate->set_open(false);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(24);
  const std::uint64_t t1 = async.start(x0);
  ASSERT_GT(t1, 0u);
  gate->wait_entered(2);               // the worker is inside the solve: "the deadline passed"
  EXPECT_EQ(async.poll(t1), nullptr);  // no result yet
  async.abandon(t1);
  EXPECT_TRUE(async.busy());
  EXPECT_EQ(async.start(x0), 0u);      // never two solves in flight
  gate->set_open(true);
  ASSERT_NE(wait_for(async, t1), nullptr);  // the late result arrives ...
  const std::uint64_t t2 = async.start(x0);  // ... and the next period may start again
  EXPECT_GT(t2, t1);
  EXPECT_EQ(async.poll(t2 + 1), nullptr);  // a ticket that was never issued
  EXPECT_EQ(async.abandoned(), 1);
  ASSERT_NE(wait_for(async, t2), nullptr);
}

// The loop's rule on real threads, period by period: the fallback exactly when the
// optimizer is late (the gate closed at the deadline) or busy (still on it).
TEST(AsyncOptimizer, TheFallbackExactlyWhenTheOptimizerIsLateOrBusy) {
  const ControllerArtifact& a = artifact();
  auto gated = std::make_unique<GatedSolver>(make_solver("admm", a));
  GatedSolver* gate = gated.get();
  AsyncOptimizer async(std::move(gated), a.n);
  TubeControllerOptions law;
  law.offset_free = false;
  TubeController ctrl(a, nullptr, law);
  const Eigen::VectorXd x_tilde = Eigen::VectorXd::Zero(a.n);
  ctrl.reset(x_tilde);
  // Period k's solve stays behind the gate for `hold[k]` periods (0: done in time).
  const int hold[12] = {0, 0, 2, 0, 0, 0, 1, 0, 0, 3, 0, 0};
  int late = 0, busy = 0, used = 0, fallbacks = 0, entered = 1, release_at = -1;
  for (int k = 0; k < 12; ++k) {
    if (k == release_at) {
      gate->set_open(true);
      while (async.busy()) std::this_thread::sleep_for(100us);
    }
    const Eigen::VectorXd& xb = ctrl.prepare(x_tilde);
    if (!async.busy()) gate->set_open(hold[k] == 0);
    const std::uint64_t ticket = async.start(xb);
    const SolveResult* r = nullptr;
    if (ticket != 0) {
      gate->wait_entered(++entered);
      if (hold[k] == 0) {
        r = wait_for(async, ticket);  // done before the deadline
        ASSERT_NE(r, nullptr);
        ++used;
      } else {
        EXPECT_EQ(async.poll(ticket), nullptr);
        async.abandon(ticket);
        ++late;
        release_at = k + hold[k];
      }
    } else {
      ++busy;
    }
    const ControlStep& s = ctrl.finish(a.u_eq, r);
    fallbacks += s.fallback;
    EXPECT_EQ(s.fallback, r == nullptr) << "period " << k;
    EXPECT_TRUE(s.u.allFinite());
  }
  gate->set_open(true);  // the last late solve finishes before the optimizer is destroyed
  EXPECT_EQ(late, 3);
  EXPECT_EQ(busy, 1 + 0 + 2);  // hold 2 -> 1 busy period, hold 1 -> none, hold 3 -> 2
  EXPECT_EQ(used, 12 - late - busy);
  EXPECT_EQ(fallbacks, late + busy);
  EXPECT_EQ(async.abandoned(), 3);
}

}  // namespace
}  // namespace tmpc
