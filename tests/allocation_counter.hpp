// A counter of every heap allocation, for the allocation tests: include it in exactly
// one source file of a test executable. It replaces the C allocator's entry points
// (malloc, calloc, realloc, posix_memalign, aligned_alloc, memalign, valloc) in the
// executable, forwarding to glibc's own; operator new in all its forms goes through
// them (libstdc++), and so does Eigen (std::malloc, its aligned allocator). So a
// dynamic Eigen temporary is counted, which a replaced operator new alone never saw.
// Allocations are counted on the threads that set t_counting, or on every thread
// while g_count_all is set (solvers with worker threads).
// Under AddressSanitizer the sanitizer owns malloc: kCountsAllocations is false and
// the allocation tests skip, saying so (the default build runs them).
#pragma once

#include <malloc.h>
#include <stdlib.h>

#include <atomic>
#include <cerrno>
#include <cstddef>

namespace tmpc::test {
inline thread_local bool t_counting = false;
inline std::atomic<bool> g_count_all{false};
inline std::atomic<long> g_allocations{0};
inline void count_allocation() {
  if (t_counting || g_count_all.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}
}  // namespace tmpc::test

#if defined(__SANITIZE_ADDRESS__)
#define TMPC_ALLOCATION_COUNTER_OFF 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TMPC_ALLOCATION_COUNTER_OFF 1
#endif
#endif

#ifdef TMPC_ALLOCATION_COUNTER_OFF
namespace tmpc::test {
constexpr bool kCountsAllocations = false;
}
#else
namespace tmpc::test {
constexpr bool kCountsAllocations = true;
}
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void __libc_free(void*);

void* malloc(std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_malloc(n);
}
void* calloc(std::size_t k, std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_calloc(k, n);
}
void* realloc(void* p, std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_realloc(p, n);
}
void free(void* p) noexcept { __libc_free(p); }
int posix_memalign(void** out, std::size_t alignment, std::size_t n) noexcept {
  tmpc::test::count_allocation();
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}
void* aligned_alloc(std::size_t alignment, std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_memalign(alignment, n);
}
void* memalign(std::size_t alignment, std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_memalign(alignment, n);
}
void* valloc(std::size_t n) noexcept {
  tmpc::test::count_allocation();
  return __libc_valloc(n);
}
}
#endif
