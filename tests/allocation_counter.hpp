// A counting global operator new for the allocation tests: include it in exactly one
// source file of a test executable (it replaces the executable's operator new).
// Allocations are counted on the threads that set t_counting, or on every thread
// while g_count_all is set (solvers with worker threads).
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace tmpc::test {
inline thread_local bool t_counting = false;
inline std::atomic<bool> g_count_all{false};
inline std::atomic<long> g_allocations{0};
}  // namespace tmpc::test

void* operator new(std::size_t n) {
  if (tmpc::test::t_counting || tmpc::test::g_count_all.load(std::memory_order_relaxed)) ++tmpc::test::g_allocations;
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
