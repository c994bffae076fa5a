// The optimizer thread (see async_optimizer.hpp).
#include "tmpc/runtime/async_optimizer.hpp"

#include <cerrno>
#include <stdexcept>

namespace tmpc {

AsyncOptimizer::AsyncOptimizer(std::unique_ptr<QpSolver> solver, int n)
    : solver_(std::move(solver)), x0_(Eigen::VectorXd::Zero(n)) {
  if (!solver_) throw std::invalid_argument("AsyncOptimizer: no solver");
  // The result's vectors get their final sizes from one solve here, so that copying
  // results in the loop never allocates.
  result_ = solver_->solve(x0_);
  solver_->reset();
  if (sem_init(&wake_, 0, 0) != 0) throw std::runtime_error("AsyncOptimizer: sem_init failed");
  worker_ = std::thread([this] { run(); });
}

AsyncOptimizer::~AsyncOptimizer() {
  stop_.store(true, std::memory_order_release);
  sem_post(&wake_);
  worker_.join();
  sem_destroy(&wake_);
}

std::uint64_t AsyncOptimizer::start(const Eigen::VectorXd& x0) {
  if (busy() || x0.size() != x0_.size()) return 0;
  x0_ = x0;  // same size: no allocation
  const std::uint64_t ticket = ++next_ticket_;
  requested_.store(ticket, std::memory_order_release);
  sem_post(&wake_);
  return ticket;
}

const SolveResult* AsyncOptimizer::poll(std::uint64_t ticket) const {
  if (ticket == 0 || finished_.load(std::memory_order_acquire) != ticket) return nullptr;
  return &result_;
}

void AsyncOptimizer::abandon(std::uint64_t ticket) {
  if (ticket != 0) ++abandoned_;
}

void AsyncOptimizer::run() {
  for (;;) {
    while (sem_wait(&wake_) != 0 && errno == EINTR) {
    }
    if (stop_.load(std::memory_order_acquire)) break;
    const std::uint64_t ticket = requested_.load(std::memory_order_acquire);
    if (ticket == finished_.load(std::memory_order_acquire)) continue;
    const SolveResult& r = solver_->solve(x0_);
    result_.status = r.status;
    result_.iterations = r.iterations;
    result_.primal_residual = r.primal_residual;
    result_.dual_residual = r.dual_residual;
    result_.objective = r.objective;
    result_.solve_us = r.solve_us;
    result_.restarts = r.restarts;
    result_.z = r.z;
    result_.y = r.y;
    finished_.store(ticket, std::memory_order_release);
  }
}

}  // namespace tmpc
