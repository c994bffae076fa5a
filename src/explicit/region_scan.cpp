// Region table and the scan of thesis Algorithm 4.1 (sequential or over OpenMP threads).
#include <omp.h>

#include <climits>

#include "tmpc/explicit/point_location.hpp"

namespace tmpc {

RegionTable RegionTable::from(const std::vector<CriticalRegion>& regions) {
  RegionTable t;
  t.n = regions.empty() ? 0 : static_cast<int>(regions.front().set.H.cols());
  t.row_begin.push_back(0);
  for (const CriticalRegion& r : regions) {
    for (Eigen::Index i = 0; i < r.set.H.rows(); ++i) {
      for (Eigen::Index j = 0; j < r.set.H.cols(); ++j) t.H.push_back(r.set.H(i, j));
      t.k.push_back(r.set.k(i));
    }
    t.row_begin.push_back(static_cast<int>(t.k.size()));
  }
  return t;
}

bool RegionTable::contains(int region, const double* th, double tol) const {
  const int end = row_begin[static_cast<std::size_t>(region) + 1];
  for (int r = row_begin[static_cast<std::size_t>(region)]; r < end; ++r) {
    const double* h = H.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(n);
    double v = -k[static_cast<std::size_t>(r)];
    for (int j = 0; j < n; ++j) v += h[j] * th[j];
    if (v > tol) return false;
  }
  return true;
}

int RegionScan::locate(const Eigen::VectorXd& th) const {
  const RegionTable& t = *t_;
  const int regions = t.regions();
  if (th.size() != t.n) return -1;
  if (threads_ <= 1) {
    for (int i = 0; i < regions; ++i) {
      if (t.contains(i, th.data())) return i;
    }
    return -1;
  }
  int best = INT_MAX;
#pragma omp parallel num_threads(threads_) reduction(min : best)
  {
    const int id = omp_get_thread_num(), count = omp_get_num_threads();
    const int begin = static_cast<int>(static_cast<long long>(regions) * id / count);
    const int end = static_cast<int>(static_cast<long long>(regions) * (id + 1) / count);
    for (int i = begin; i < end; ++i) {
      if (t.contains(i, th.data())) {
        best = i;
        break;
      }
    }
  }
  return best == INT_MAX ? -1 : best;
}

}  // namespace tmpc
