// Online point location in an explicit MPC partition (thesis Algorithm 4.1):
//   find i with H_i th <= k_i, then z = Kz_i th + kz_i.
// RegionScan is the thesis' sequential scan, split over OpenMP threads; SearchTree is
// the binary search tree over the regions' hyperplanes (Tondel, Johansen and Bemporad
// 2003). Both return the lowest-index region that contains th within the tolerance, so
// ties on shared facets are resolved the same way; -1 means th lies outside the
// partition (outside the feasible set or the domain: the runtime falls back).
// Neither allocates.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "tmpc/explicit/mpqp.hpp"

namespace tmpc {

constexpr double kLocateTolerance = 1e-9;

/// Flat region storage for the online path.
struct RegionTable {
  int n = 0;                   ///< parameter dimension
  std::vector<double> H;       ///< all rows, row-major, n numbers a row
  std::vector<double> k;
  std::vector<int> row_begin;  ///< region i owns rows [row_begin[i], row_begin[i + 1])
  int regions() const { return row_begin.empty() ? 0 : static_cast<int>(row_begin.size()) - 1; }
  bool contains(int region, const double* th, double tol = kLocateTolerance) const;
  static RegionTable from(const std::vector<CriticalRegion>& regions);
};

class RegionScan {
 public:
  /// threads <= 1: sequential (Algorithm 4.1); otherwise the regions are split into
  /// `threads` contiguous blocks scanned in parallel.
  explicit RegionScan(const RegionTable& t, int threads = 1) : t_(&t), threads_(threads) {}
  int locate(const Eigen::VectorXd& th) const;

 private:
  const RegionTable* t_;
  int threads_;
};

struct SearchTreeStats {
  int nodes = 0, leaves = 0, depth = 0, hyperplanes = 0, lps = 0;
  int max_leaf_regions = 0;
  double seconds = 0.0;
};

class SearchTree {
 public:
  struct Node {
    int hyperplane = -1;       ///< -1: a leaf
    int left = -1, right = -1; ///< children: left holds h'th <= b
    int leaf_begin = 0, leaf_end = 0;
  };
  /// Builds the tree; every region is classified against a split hyperplane exactly
  /// (by the facet it shares with it, or by two LPs), so a region that straddles it goes
  /// to both children.
  static SearchTree build(const std::vector<CriticalRegion>& regions, const Box& domain);
  int locate(const RegionTable& t, const Eigen::VectorXd& th) const;

  std::vector<double> hp, hb;  ///< split hyperplanes (row-major) and offsets
  std::vector<Node> nodes;
  std::vector<int> leaf_regions;
  SearchTreeStats stats;
};

}  // namespace tmpc
