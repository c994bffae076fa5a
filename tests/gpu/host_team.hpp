// A team of host threads with the interface of the device's thread block
// (tmpc/gpu/admm_kernel.hpp), so the ADMM kernel code runs and is checked without a
// GPU: a barrier, all-reductions summed in one fixed order, one clock.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

namespace tmpc::test {

class HostBarrier {
 public:
  explicit HostBarrier(int count) : count_(count) {}
  void wait() {
    std::unique_lock<std::mutex> lock(mu_);
    const long gen = generation_;
    if (++arrived_ == count_) {
      arrived_ = 0;
      ++generation_;
      cv_.notify_all();
      return;
    }
    cv_.wait(lock, [&] { return generation_ != gen; });
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  int count_, arrived_ = 0;
  long generation_ = 0;
};

struct HostTeamShared {
  explicit HostTeamShared(int size) : barrier(size), red(static_cast<std::size_t>(size)) {}
  HostBarrier barrier;
  std::vector<double> red;  // holds float and double members exactly
};

struct HostTeam {
  int rank, size;
  HostTeamShared* shared;
  void sync() { shared->barrier.wait(); }
  template <class R, class Op>
  R reduce(R v, Op op) {
    sync();
    shared->red[static_cast<std::size_t>(rank)] = v;
    sync();
    R r = static_cast<R>(shared->red[0]);
    for (int i = 1; i < size; ++i) r = op(r, static_cast<R>(shared->red[static_cast<std::size_t>(i)]));
    sync();
    return r;
  }
  template <class R>
  R sum(R v) {
    return reduce(v, [](R a, R b) { return a + b; });
  }
  template <class R>
  R max(R v) {
    return reduce(v, [](R a, R b) { return (a != a || a > b) ? a : b; });
  }
  long long now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
};

/// Run body(team) on `size` threads (size 1: on the calling thread).
template <class Body>
void run_team(int size, Body body) {
  HostTeamShared shared(size);
  if (size == 1) {
    HostTeam t{0, 1, &shared};
    body(t);
    return;
  }
  std::vector<std::thread> threads;
  for (int r = 0; r < size; ++r) {
    threads.emplace_back([&, r] {
      HostTeam t{r, size, &shared};
      body(t);
    });
  }
  for (std::thread& th : threads) th.join();
}

}  // namespace tmpc::test
