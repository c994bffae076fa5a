// The allocation counter sees what it must: Eigen's dynamic temporaries (a product, an
// inverse), operator new in its plain, array, nothrow and aligned forms, and the C
// allocator's entry points; and nothing on a thread that does not count.
#include <cstdlib>
#include <new>
#include <thread>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "allocation_counter.hpp"

namespace tmpc {
namespace {

using test::g_allocations;
using test::t_counting;

/// Keeps a new-expression from being elided (the compiler may drop a new/delete pair).
template <class T>
void keep(T* p) {
  T* volatile v = p;
  delete v;
}
template <class T>
void keep_array(T* p) {
  T* volatile v = p;
  delete[] v;
}

long counted(void (*f)()) {
  const long before = g_allocations.load();
  t_counting = true;
  f();
  t_counting = false;
  return g_allocations.load() - before;
}

TEST(AllocationCounter, CountsEigensDynamicTemporaries) {
  if (!test::kCountsAllocations) GTEST_SKIP() << "AddressSanitizer owns malloc in this build";
  static Eigen::MatrixXd A = Eigen::MatrixXd::Random(10, 10) + 10.0 * Eigen::MatrixXd::Identity(10, 10);
  static Eigen::VectorXd x = Eigen::VectorXd::Random(10);
  static double sink = 0.0;
  EXPECT_GE(counted([] { sink += (A * x).sum(); }), 1);             // the product's temporary
  EXPECT_GE(counted([] { sink += A.inverse().trace(); }), 1);        // inverse and its LU
  static Eigen::VectorXd y = Eigen::VectorXd::Zero(10);
  EXPECT_EQ(counted([] { y.noalias() = A * x; }), 0);               // into existing storage: none
  EXPECT_EQ(counted([] { y = A.col(0) + x; }), 0);
  EXPECT_GT(sink, -1e300);
}

TEST(AllocationCounter, CountsEveryFormOfNewAndTheCAllocator) {
  if (!test::kCountsAllocations) GTEST_SKIP() << "AddressSanitizer owns malloc in this build";
  EXPECT_EQ(counted([] { keep(new int(3)); }), 1);
  EXPECT_EQ(counted([] { keep_array(new double[7]); }), 1);
  EXPECT_EQ(counted([] { keep(new (std::nothrow) long(1)); }), 1);
  EXPECT_EQ(counted([] {
              struct alignas(128) Wide {
                double v[4];
              };
              keep(new Wide);
            }),
            1);
  EXPECT_EQ(counted([] { std::free(std::malloc(16)); }), 1);
  EXPECT_EQ(counted([] { std::free(std::calloc(4, 8)); }), 1);
  EXPECT_EQ(counted([] { std::free(std::realloc(nullptr, 32)); }), 1);
  EXPECT_EQ(counted([] { std::free(std::aligned_alloc(64, 128)); }), 1);
  EXPECT_EQ(counted([] {
              void* p = nullptr;
              if (posix_memalign(&p, 64, 100) == 0) std::free(p);
            }),
            1);
  EXPECT_EQ(counted([] { std::vector<int> v(100); }), 1);
}

TEST(AllocationCounter, CountsOnlyTheThreadsThatAskUnlessAllDo) {
  if (!test::kCountsAllocations) GTEST_SKIP() << "AddressSanitizer owns malloc in this build";
  const long before = g_allocations.load();
  std::thread([] { keep(new int(1)); }).join();  // this thread does not count
  const long other = g_allocations.load() - before;
  EXPECT_LE(other, 1);  // std::thread's own start-up state is allocated on this thread
  test::g_count_all = true;
  const long b2 = g_allocations.load();
  std::thread([] { keep(new int(1)); }).join();
  test::g_count_all = false;
  EXPECT_GE(g_allocations.load() - b2, 2);  // the thread's state and its int
}

}  // namespace
}  // namespace tmpc
