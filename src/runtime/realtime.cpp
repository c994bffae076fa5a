// Real-time thread set-up and the periodic clock (see realtime.hpp).
#include "tmpc/runtime/realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace tmpc {

namespace {
// Touch the stack once so page faults do not happen inside the loop.
void prefault(std::size_t bytes) {
  volatile unsigned char* p = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  for (std::size_t i = 0; i < bytes; i += 4096) p[i] = 0;
}
}  // namespace

RealTimeReport apply_realtime(const RealTimeSettings& s) {
  RealTimeReport r;
  if (s.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      r.memory_locked = true;
    } else {
      r.not_set.push_back(std::string("mlockall: ") + std::strerror(errno) + " (needs CAP_IPC_LOCK or a memlock limit)");
    }
  }
  if (s.prefault_stack > 0) prefault(s.prefault_stack);
  if (s.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(s.cpu, &set);
    const int e = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    if (e == 0) {
      r.affinity = true;
    } else {
      r.not_set.push_back("CPU affinity " + std::to_string(s.cpu) + ": " + std::strerror(e));
    }
  }
  if (s.priority > 0) {
    sched_param p{};
    p.sched_priority = s.priority;
    const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
    if (e == 0) {
      r.scheduler = true;
    } else {
      r.not_set.push_back("SCHED_FIFO priority " + std::to_string(s.priority) + ": " + std::strerror(e) +
                          " (needs CAP_SYS_NICE or an rtprio limit)");
    }
  }
  return r;
}

timespec add_ns(timespec t, long ns) {
  t.tv_nsec += ns;
  while (t.tv_nsec >= 1000000000L) {
    t.tv_nsec -= 1000000000L;
    ++t.tv_sec;
  }
  return t;
}

double diff_us(const timespec& a, const timespec& b) {
  return static_cast<double>(a.tv_sec - b.tv_sec) * 1e6 + static_cast<double>(a.tv_nsec - b.tv_nsec) * 1e-3;
}

PeriodicClock::PeriodicClock(double period_s) : period_ns_(static_cast<long>(period_s * 1e9)) {
  if (!(period_s > 0.0) || period_s > 10.0) throw std::invalid_argument("PeriodicClock: period must be in (0, 10] s");
  clock_gettime(CLOCK_MONOTONIC, &start_);
  next_ = start_;
}

double PeriodicClock::wait() {
  next_ = add_ns(next_, period_ns_);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next_, nullptr) == EINTR) {
  }
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  if (woke_) last_period_us_ = diff_us(now, last_wake_);
  last_wake_ = now;
  woke_ = true;
  const double late_us = diff_us(now, next_);
  const long behind = static_cast<long>(late_us * 1e3 / static_cast<double>(period_ns_));  // whole periods
  if (behind > 0) {
    next_ = add_ns(next_, behind * period_ns_);
    skipped_ += behind;
  }
  return late_us;
}

double PeriodicClock::elapsed_s() const {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return diff_us(now, start_) * 1e-6;
}

}  // namespace tmpc
