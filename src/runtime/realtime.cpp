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

PeriodicClock::PeriodicClock(double period_s) : LoopClock(period_s) { start(); }

std::int64_t PeriodicClock::now_ns() const {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1000000000LL + now.tv_nsec;
}

void PeriodicClock::sleep_until_ns(std::int64_t t_ns) {
  timespec t{};
  t.tv_sec = static_cast<time_t>(t_ns / 1000000000LL);
  t.tv_nsec = static_cast<long>(t_ns % 1000000000LL);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
  }
}

timespec PeriodicClock::next_wakeup() const {
  timespec t{};
  t.tv_sec = static_cast<time_t>(next_wakeup_ns() / 1000000000LL);
  t.tv_nsec = static_cast<long>(next_wakeup_ns() % 1000000000LL);
  return t;
}

}  // namespace tmpc
