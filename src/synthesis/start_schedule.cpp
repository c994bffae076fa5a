// The shared start schedules (see start_schedule.hpp).
#include "tmpc/synthesis/start_schedule.hpp"

#include <list>
#include <mutex>

namespace tmpc {

namespace {

/// A schedule and the inputs it was computed from.
struct Entry {
  Eigen::MatrixXd A_a, C, Q, R, L, P0;
  double tolerance = 0.0;
  int max_steps = 0;
  std::shared_ptr<const StartSchedule> schedule;

  bool computed_from(const KalmanDesign& k, const Eigen::MatrixXd& P0_, double tolerance_, int max_steps_) const {
    auto same = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
      return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
    };
    return tolerance == tolerance_ && max_steps == max_steps_ && same(A_a, k.A_a) && same(C, k.C) && same(Q, k.Q) &&
           same(R, k.R) && same(L, k.L) && same(P0, P0_);
  }
};

std::mutex& cache_mutex() {
  static std::mutex m;
  return m;
}

std::list<Entry>& cache() {  // most recently used first
  static std::list<Entry> c;
  return c;
}

std::shared_ptr<const StartSchedule> find(const KalmanDesign& k, const Eigen::MatrixXd& P0, double tolerance, int max_steps) {
  std::list<Entry>& c = cache();
  for (auto it = c.begin(); it != c.end(); ++it) {
    if (it->computed_from(k, P0, tolerance, max_steps)) {
      c.splice(c.begin(), c, it);
      return c.front().schedule;
    }
  }
  return nullptr;
}

}  // namespace

std::shared_ptr<const StartSchedule> shared_start_schedule(const KalmanDesign& k, const Eigen::MatrixXd& P0, double tolerance,
                                                           int max_steps) {
  {
    const std::lock_guard<std::mutex> lock(cache_mutex());
    if (auto s = find(k, P0, tolerance, max_steps)) return s;
  }
  // Computed outside the lock (a second controller of another filter need not wait);
  // where two threads computed the same schedule, the first stored is kept.
  auto s = std::make_shared<StartSchedule>();
  s->gains = start_gains(k, P0, tolerance, max_steps, &s->innovation_sds);
  const std::lock_guard<std::mutex> lock(cache_mutex());
  if (auto stored = find(k, P0, tolerance, max_steps)) return stored;
  std::list<Entry>& c = cache();
  c.push_front(Entry{k.A_a, k.C, k.Q, k.R, k.L, P0, tolerance, max_steps, s});
  while (static_cast<int>(c.size()) > kStartScheduleCache) c.pop_back();
  return s;
}

}  // namespace tmpc
