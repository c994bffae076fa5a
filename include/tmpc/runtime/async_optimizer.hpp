// The optimizer thread of the real-time loop (thesis Figure 6.3): the period starts a
// solve and goes on (fallback computed at once); at the deadline it polls; a solve
// that is not done is abandoned (its result, when it comes, is never used) and no new
// solve starts while one is in flight. Wake-up by a POSIX semaphore (sem_post is
// lock-free and async-signal-safe), completion by atomics: the real-time thread never
// waits on a lock the worker holds, and nothing allocates after construction.
#pragma once

#include <semaphore.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include <Eigen/Core>

#include "tmpc/solvers/solver.hpp"

namespace tmpc {

/// What the real-time loop needs of its optimizer: start a solve, poll for it without
/// blocking, abandon it at the deadline. AsyncOptimizer runs a QpSolver on its own
/// thread; tests drive the loop with one whose solve times they script.
class Optimizer {
 public:
  virtual ~Optimizer() = default;
  /// A ticket (> 0), or 0 when a solve is still in flight or x0 is refused.
  virtual std::uint64_t start(const Eigen::VectorXd& x0) = 0;
  /// The result of `ticket` once finished, else null; never blocks.
  virtual const SolveResult* poll(std::uint64_t ticket) const = 0;
  /// The deadline passed without a result for `ticket`.
  virtual void abandon(std::uint64_t ticket) = 0;
  virtual bool busy() const = 0;
};

class AsyncOptimizer final : public Optimizer {
 public:
  /// Takes the solver; starts the worker thread. `n` is the size of x0.
  AsyncOptimizer(std::unique_ptr<QpSolver> solver, int n);
  ~AsyncOptimizer();  ///< stops the worker (after the solve in flight, if any)
  AsyncOptimizer(const AsyncOptimizer&) = delete;
  AsyncOptimizer& operator=(const AsyncOptimizer&) = delete;

  /// Starts a solve from x0 and returns its ticket (> 0), or 0 when a solve is still
  /// in flight (or x0 has the wrong size): the period then uses the fallback.
  std::uint64_t start(const Eigen::VectorXd& x0) override;
  /// The result of `ticket` once that solve has finished, else null; never blocks.
  /// The result stays valid until the next start().
  const SolveResult* poll(std::uint64_t ticket) const override;
  bool busy() const override { return requested_.load(std::memory_order_acquire) != finished_.load(std::memory_order_acquire); }
  /// Solves abandoned at a deadline (finished after it, or never used).
  long abandoned() const { return abandoned_; }
  /// Mark `ticket` abandoned (the deadline passed without a result).
  void abandon(std::uint64_t ticket) override;
  const char* solver_name() const { return solver_->name(); }

 private:
  void run();
  std::unique_ptr<QpSolver> solver_;
  Eigen::VectorXd x0_;
  SolveResult result_;
  std::atomic<std::uint64_t> requested_{0}, finished_{0};
  std::atomic<bool> stop_{false};
  std::uint64_t next_ticket_ = 0;
  long abandoned_ = 0;
  sem_t wake_;
  std::thread worker_;
};

}  // namespace tmpc
