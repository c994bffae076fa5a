// Binary search tree over the partition's hyperplanes (Tondel, Johansen and Bemporad
// 2003): each node splits the candidate regions by one facet hyperplane, chosen among
// sampled facets of the node's regions to minimize the larger child.
#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <unordered_map>

#include "tmpc/sets/lp.hpp"
#include "tmpc/explicit/point_location.hpp"

namespace tmpc {

namespace {

constexpr double kTie = 1e-7;       // |h'th - b| below this: descend both ways
constexpr double kClassify = 1e-9;  // LP slack of "entirely on one side"
constexpr int kSampled = 48, kExact = 4, kMaxDepth = 32, kLeafRegions = 6;
constexpr double kMinShrink = 0.9;  // a child must hold at most this fraction of the node's regions

enum Side : char { kLeft = 1, kRight = 2, kBoth = 3 };

class Builder {
 public:
  Builder(const std::vector<CriticalRegion>& regions, const Box& domain, SearchTree& tree)
      : regions_(regions), domain_(domain), tree_(tree), n_(static_cast<int>(domain.lo.size())) {
    // Unique hyperplanes, canonical sign (first nonzero entry positive), and for every
    // region the side its facets put it on.
    facets_.resize(regions.size());
    std::map<std::vector<long long>, int> ids;
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const CriticalRegion& cr = regions[r];
      for (Eigen::Index i = 0; i < cr.set.H.rows(); ++i) {
        if (cr.boundary[static_cast<std::size_t>(i)]) continue;
        Eigen::RowVectorXd a = cr.set.H.row(i);
        double b = cr.set.k(i);
        Side side = kLeft;
        Eigen::Index first = 0;
        while (first < a.size() && std::abs(a(first)) < 1e-12) ++first;
        if (first < a.size() && a(first) < 0) {
          a = -a;
          b = -b;
          side = kRight;
        }
        std::vector<long long> key(static_cast<std::size_t>(n_) + 1);
        for (int j = 0; j < n_; ++j) key[static_cast<std::size_t>(j)] = std::llround(a(j) * 1e8);
        key[static_cast<std::size_t>(n_)] = std::llround(b * 1e8);
        auto [it, fresh] = ids.emplace(key, static_cast<int>(normals_.size()));
        if (fresh) {
          normals_.push_back(a);
          offsets_.push_back(b);
        }
        facets_[r].emplace(it->second, side);
      }
    }
    tree_.stats.hyperplanes = static_cast<int>(normals_.size());
    lp_.resize(regions.size());
  }

  void run() {
    std::vector<int> all(regions_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    tree_.nodes.emplace_back();
    split(0, all, 0);
  }

 private:
  Side classify(int r, int h) {
    const auto f = facets_[static_cast<std::size_t>(r)].find(h);
    if (f != facets_[static_cast<std::size_t>(r)].end()) return f->second;
    const long long key = static_cast<long long>(r) * static_cast<long long>(normals_.size()) + h;
    const auto c = cache_.find(key);
    if (c != cache_.end()) return c->second;
    const CriticalRegion& cr = regions_[static_cast<std::size_t>(r)];
    const Eigen::VectorXd a = normals_[static_cast<std::size_t>(h)].transpose();
    const double b = offsets_[static_cast<std::size_t>(h)];
    Side s = kBoth;
    // Quick answer from the Chebyshev ball when the hyperplane cuts it.
    const double at_center = a.dot(cr.center) - b;
    if (std::abs(at_center) < cr.radius) {
      s = kBoth;
    } else {
      auto& ws = lp_[static_cast<std::size_t>(r)];
      if (!ws) ws = std::make_unique<LpWorkspace>(cr.set.H, cr.set.k, domain_.lo, domain_.hi);
      const LpResult mx = ws->minimize(-a);
      const LpResult mn = ws->minimize(a);
      tree_.stats.lps += 2;
      const bool left = mx.status == LpStatus::Optimal && -mx.value <= b + kClassify;
      const bool right = mn.status == LpStatus::Optimal && mn.value >= b - kClassify;
      s = left ? kLeft : right ? kRight : kBoth;
    }
    cache_.emplace(key, s);
    return s;
  }

  void make_leaf(int node, const std::vector<int>& set) {
    SearchTree::Node& nd = tree_.nodes[static_cast<std::size_t>(node)];
    nd.hyperplane = -1;
    nd.leaf_begin = static_cast<int>(tree_.leaf_regions.size());
    tree_.leaf_regions.insert(tree_.leaf_regions.end(), set.begin(), set.end());
    nd.leaf_end = static_cast<int>(tree_.leaf_regions.size());
    ++tree_.stats.leaves;
    tree_.stats.max_leaf_regions = std::max(tree_.stats.max_leaf_regions, static_cast<int>(set.size()));
  }

  void split(int node, const std::vector<int>& set, int depth) {
    tree_.stats.depth = std::max(tree_.stats.depth, depth);
    if (set.size() <= static_cast<std::size_t>(kLeafRegions) || depth >= kMaxDepth) {
      make_leaf(node, set);
      return;
    }
    // Candidates: facets of the node's regions, a deterministic sample of them.
    std::vector<int> cand;
    for (int r : set) {
      for (const auto& f : facets_[static_cast<std::size_t>(r)]) cand.push_back(f.first);
    }
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
    std::shuffle(cand.begin(), cand.end(), rng_);
    if (cand.size() > static_cast<std::size_t>(kSampled)) cand.resize(kSampled);
    // Estimate each split by the regions' Chebyshev centers, then classify the best exactly.
    std::vector<std::pair<int, int>> est;
    for (int h : cand) {
      int l = 0, rgt = 0;
      for (int r : set) {
        const double v = normals_[static_cast<std::size_t>(h)].dot(regions_[static_cast<std::size_t>(r)].center) -
                         offsets_[static_cast<std::size_t>(h)];
        (v <= 0 ? l : rgt) += 1;
      }
      est.emplace_back(std::max(l, rgt), h);
    }
    std::sort(est.begin(), est.end());
    int best_h = -1;
    std::size_t best_max = set.size();
    std::vector<int> best_l, best_r;
    for (std::size_t e = 0; e < est.size() && e < static_cast<std::size_t>(kExact); ++e) {
      const int h = est[e].second;
      std::vector<int> l, rgt;
      for (int r : set) {
        const Side s = classify(r, h);
        if (s & kLeft) l.push_back(r);
        if (s & kRight) rgt.push_back(r);
        if (l.size() >= best_max && rgt.size() >= best_max) break;
      }
      const std::size_t mx = std::max(l.size(), rgt.size());
      if (mx < best_max && !l.empty() && !rgt.empty()) {
        best_max = mx;
        best_h = h;
        best_l = std::move(l);
        best_r = std::move(rgt);
      }
    }
    // A split that leaves a child almost as large as the node (hyperplanes cutting most
    // regions, common with 24 parameters) only duplicates regions: stop with a leaf scan.
    if (best_h < 0 || static_cast<double>(best_max) > kMinShrink * static_cast<double>(set.size())) {
      make_leaf(node, set);
      return;
    }
    const int hp_index = static_cast<int>(tree_.hb.size());
    for (int j = 0; j < n_; ++j) tree_.hp.push_back(normals_[static_cast<std::size_t>(best_h)](j));
    tree_.hb.push_back(offsets_[static_cast<std::size_t>(best_h)]);
    const int left = static_cast<int>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    const int right = static_cast<int>(tree_.nodes.size());
    tree_.nodes.emplace_back();
    SearchTree::Node& nd = tree_.nodes[static_cast<std::size_t>(node)];
    nd.hyperplane = hp_index;
    nd.left = left;
    nd.right = right;
    split(left, best_l, depth + 1);
    split(right, best_r, depth + 1);
  }

  const std::vector<CriticalRegion>& regions_;
  const Box& domain_;
  SearchTree& tree_;
  int n_;
  std::vector<Eigen::RowVectorXd> normals_;
  std::vector<double> offsets_;
  std::vector<std::map<int, Side>> facets_;
  std::unordered_map<long long, Side> cache_;
  std::vector<std::unique_ptr<LpWorkspace>> lp_;  // one warm-started LP model a region
  std::mt19937 rng_{7};
};

}  // namespace

SearchTree SearchTree::build(const std::vector<CriticalRegion>& regions, const Box& domain) {
  const auto t0 = std::chrono::steady_clock::now();
  SearchTree tree;
  if (regions.empty()) {
    tree.nodes.emplace_back();
    tree.stats.nodes = 1;
    tree.stats.leaves = 1;
    return tree;
  }
  Builder b(regions, domain, tree);
  b.run();
  tree.stats.nodes = static_cast<int>(tree.nodes.size());
  tree.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return tree;
}

int SearchTree::locate(const RegionTable& t, const Eigen::VectorXd& th) const {
  if (th.size() != t.n || nodes.empty()) return -1;
  constexpr int kStack = 512;
  int stack[kStack];
  int sp = 0;
  stack[sp++] = 0;
  int best = INT_MAX;
  const int n = t.n;
  while (sp > 0) {
    const Node& nd = nodes[static_cast<std::size_t>(stack[--sp])];
    if (nd.hyperplane < 0) {
      for (int i = nd.leaf_begin; i < nd.leaf_end; ++i) {
        const int r = leaf_regions[static_cast<std::size_t>(i)];
        if (r < best && t.contains(r, th.data())) best = r;
      }
      continue;
    }
    const double* h = hp.data() + static_cast<std::size_t>(nd.hyperplane) * static_cast<std::size_t>(n);
    double v = -hb[static_cast<std::size_t>(nd.hyperplane)];
    for (int j = 0; j < n; ++j) v += h[j] * th(j);
    if (sp + 2 > kStack) {  // cannot happen for trees of sane depth; stay correct anyway
      for (int r = 0; r < t.regions(); ++r) {
        if (t.contains(r, th.data())) return r;
      }
      return -1;
    }
    if (v >= -kTie) stack[sp++] = nd.right;
    if (v <= kTie) stack[sp++] = nd.left;
  }
  return best == INT_MAX ? -1 : best;
}

}  // namespace tmpc
