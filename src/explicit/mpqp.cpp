// mpQP partition by geometric exploration with QP-identified neighbours and sampled
// coverage passes (see mpqp.hpp).
#include "tmpc/explicit/mpqp.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "critical_region.hpp"
#include "tmpc/sets/lp.hpp"
#include "tmpc/solvers/solver.hpp"

namespace tmpc {

MpQp MpQp::from_parametric(const ParametricQp& qp, const Box& domain) {
  const int nz = qp.nz(), nt = qp.nx(), nc = qp.nc();
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("mpQP: " + what);
  };
  need(qp.H.cols() == nz && qp.F.rows() == nz && qp.f0.size() == nz, "H, F, f0 sizes disagree");
  need(qp.A.cols() == nz && qp.E.rows() == nc && qp.E.cols() == nt && qp.lo0.size() == nc && qp.hi0.size() == nc,
       "A, E, lo0, hi0 sizes disagree");
  need(domain.lo.size() == nt && domain.hi.size() == nt, "the domain has " + std::to_string(domain.lo.size()) +
                                                            " coordinates, the parameter " + std::to_string(nt));
  need(!domain.empty() && domain.lo.allFinite() && domain.hi.allFinite(), "the domain must be a finite, non-empty box");
  need(Eigen::LLT<Eigen::MatrixXd>(qp.H).info() == Eigen::Success, "H must be positive definite");
  MpQp p;
  p.H = 0.5 * (qp.H + qp.H.transpose());
  p.F = qp.F;
  p.f = qp.f0;
  p.domain = domain;
  std::vector<Eigen::RowVectorXd> g, s, tr;
  std::vector<double> wv, tv;
  const double gmax = std::max(qp.A.rowwise().norm().maxCoeff(), 1e-300);
  auto add = [&](const Eigen::RowVectorXd& gi, const Eigen::RowVectorXd& si, double wi) {
    if (gi.norm() <= 1e-10 * gmax) {  // a pure parameter constraint: -S_i th <= w_i
      const double n = si.norm();
      if (n > 0.0) {
        tr.push_back(-si / n);
        tv.push_back(wi / n);
      } else if (wi < 0.0) {
        throw std::invalid_argument("mpQP: a constraint 0 <= " + std::to_string(wi) + " can never hold");
      }
      return;
    }
    const double n = std::sqrt(gi.squaredNorm() + si.squaredNorm());
    const Eigen::RowVectorXd gn = gi / n, sn = si / n;
    const double wn = wi / n;
    for (std::size_t k = 0; k < g.size(); ++k) {  // merge duplicates, keep the tighter
      if ((g[k] - gn).cwiseAbs().maxCoeff() < 1e-12 && (s[k] - sn).cwiseAbs().maxCoeff() < 1e-12) {
        wv[k] = std::min(wv[k], wn);
        return;
      }
    }
    g.push_back(gn);
    s.push_back(sn);
    wv.push_back(wn);
  };
  for (int i = 0; i < nc; ++i) {
    if (std::isfinite(qp.hi0(i))) add(qp.A.row(i), -qp.E.row(i), qp.hi0(i));
    if (std::isfinite(qp.lo0(i))) add(-qp.A.row(i), qp.E.row(i), -qp.lo0(i));
  }
  p.G.resize(static_cast<Eigen::Index>(g.size()), nz);
  p.S.resize(static_cast<Eigen::Index>(g.size()), nt);
  p.w.resize(static_cast<Eigen::Index>(g.size()));
  for (std::size_t k = 0; k < g.size(); ++k) {
    p.G.row(static_cast<Eigen::Index>(k)) = g[k];
    p.S.row(static_cast<Eigen::Index>(k)) = s[k];
    p.w(static_cast<Eigen::Index>(k)) = wv[k];
  }
  p.T.resize(static_cast<Eigen::Index>(tr.size()), nt);
  p.t.resize(static_cast<Eigen::Index>(tr.size()));
  for (std::size_t k = 0; k < tr.size(); ++k) {
    p.T.row(static_cast<Eigen::Index>(k)) = tr[k];
    p.t(static_cast<Eigen::Index>(k)) = tv[k];
  }
  return p;
}

ParametricQp MpQp::as_parametric() const {
  ParametricQp q;
  q.H = H;
  q.F = F;
  q.f0 = f;
  q.A = G;
  q.E = -S;
  q.hi0 = w;
  q.lo0 = Eigen::VectorXd::Constant(w.size(), -std::numeric_limits<double>::infinity());
  return q;
}

bool mpqp_feasible(const MpQp& p, const Eigen::VectorXd& th) {
  if (!p.domain.contains(th, 1e-12)) return false;
  if (p.T.rows() > 0 && ((p.T * th - p.t).array() > 1e-9).any()) return false;
  const int nz = p.nz();
  const Eigen::VectorXd inf = Eigen::VectorXd::Constant(nz, std::numeric_limits<double>::infinity());
  const LpResult lp = solve_lp(Eigen::VectorXd::Zero(nz), p.G, p.w + p.S * th, Eigen::MatrixXd(0, nz),
                               Eigen::VectorXd(0), -inf, inf);
  return lp.status == LpStatus::Optimal;
}

int Partition::locate(const Eigen::VectorXd& th, double tol) const {
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].set.contains(th, tol)) return static_cast<int>(i);
  }
  return -1;
}

namespace {

using Clock = std::chrono::steady_clock;

/// The exploration state: one problem, its QP oracle, the regions found so far.
class Explorer {
 public:
  Explorer(const MpQp& p, const MpQpOptions& opt)
      : p_(p), opt_(opt), fac_(p), rng_(opt.seed), t0_(Clock::now()) {
    SolverOptions so;
    so.warm_start = false;
    oracle_ = make_reference_solver(p.as_parametric(), so);
    part_.domain = p.domain;
  }

  Partition run() {
    // Seed at the domain's Chebyshev center (or any feasible sample).
    seed(part_.domain.center());
    drain();
    for (int pass = 0; pass < opt_.coverage_passes && !stopped(); ++pass) {
      const int holes_before = part_.stats.holes_found;
      int checked = 0;
      std::uniform_real_distribution<double> u(0.0, 1.0);
      for (int s = 0; s < opt_.coverage_samples && !stopped(); ++s) {
        Eigen::VectorXd th(p_.ntheta());
        for (int j = 0; j < p_.ntheta(); ++j) th(j) = p_.domain.lo(j) + u(rng_) * (p_.domain.hi(j) - p_.domain.lo(j));
        if (part_.locate(th) >= 0) {
          ++checked;
          continue;
        }
        ++part_.stats.lps;
        if (!mpqp_feasible(p_, th)) continue;
        ++part_.stats.holes_found;
        seed(th);
        drain();
        if (part_.locate(th) >= 0) ++checked;
      }
      part_.stats.coverage_checked = checked;
      if (part_.stats.holes_found == holes_before && !stopped()) {
        part_.stats.complete = part_.stats.unresolved_facets == 0;
        if (!part_.stats.complete) part_.stats.stop_reason = "some facets' neighbours could not be identified";
        break;
      }
    }
    if (!part_.stats.complete && part_.stats.stop_reason.empty()) {
      part_.stats.stop_reason = stopped() ? stop_reason() : "coverage passes kept finding holes";
    }
    part_.stats.seconds = elapsed();
    return std::move(part_);
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }
  bool stopped() const {
    return static_cast<int>(part_.regions.size()) >= opt_.max_regions || elapsed() > opt_.time_limit_s;
  }
  std::string stop_reason() const {
    if (static_cast<int>(part_.regions.size()) >= opt_.max_regions) {
      return "region limit " + std::to_string(opt_.max_regions) + " reached";
    }
    return "time limit " + std::to_string(opt_.time_limit_s) + " s reached";
  }

  void seed(const Eigen::VectorXd& th) { queue_.push_back(th); }

  void drain() {
    while (!queue_.empty() && !stopped()) {
      const Eigen::VectorXd th = queue_.front();
      queue_.pop_front();
      explore_point(th);
    }
  }

  // Solve the QP at th; on success fill z, y (multipliers of G z <= w + S th).
  bool solve_at(const Eigen::VectorXd& th) {
    ++part_.stats.qp_solves;
    const SolveResult& r = oracle_->solve(th);
    if (r.status != SolveStatus::Converged) return false;
    z_ = r.z;
    y_ = r.y;
    return true;
  }

  // Candidate active sets at the last solve: strongly active rows, then all rows with
  // zero slack; each reduced to a linearly independent subset (largest multipliers first).
  std::vector<std::vector<int>> candidates(const Eigen::VectorXd& th) {
    const Eigen::VectorXd slack = p_.w + p_.S * th - p_.G * z_;
    std::vector<int> strong, weak;
    for (Eigen::Index i = 0; i < slack.size(); ++i) {
      if (y_(i) > 1e-8) strong.push_back(static_cast<int>(i));
      if (slack(i) < 1e-8 || y_(i) > 1e-8) weak.push_back(static_cast<int>(i));
    }
    std::vector<std::vector<int>> out{independent(strong)};
    std::vector<int> w = independent(weak);
    if (w != out.front()) out.push_back(w);
    return out;
  }

  std::vector<int> independent(std::vector<int> rows) {
    std::sort(rows.begin(), rows.end(), [&](int a, int b) { return y_(a) > y_(b); });
    std::vector<int> kept;
    Eigen::MatrixXd basis(0, p_.nz());
    for (int r : rows) {
      Eigen::MatrixXd trial(basis.rows() + 1, p_.nz());
      trial << basis, p_.G.row(r);
      Eigen::FullPivLU<Eigen::MatrixXd> lu(trial);
      lu.setThreshold(1e-9);
      if (lu.rank() == trial.rows()) {
        basis = trial;
        kept.push_back(r);
      } else {
        ++part_.stats.licq_reduced;
      }
      if (basis.rows() == p_.nz()) break;
    }
    std::sort(kept.begin(), kept.end());
    return kept;
  }

  // Find the region at th: solve the QP there, try its candidate active sets; when th
  // sits on a degenerate set (a lower-dimensional region, a weakly active constraint)
  // move it a little and try again.
  void explore_point(Eigen::VectorXd th) {
    if (!p_.domain.contains(th, 0.0)) return;
    if (part_.locate(th) >= 0) return;
    std::normal_distribution<double> nd(0.0, 1.0);
    for (int attempt = 0; attempt < 6; ++attempt) {
      if (attempt > 0) {
        ++part_.stats.perturbed;
        Eigen::VectorXd d(p_.ntheta());
        for (Eigen::Index j = 0; j < d.size(); ++j) d(j) = nd(rng_);
        th += (0.3 * opt_.step * attempt / d.norm()) * d;
        if (!p_.domain.contains(th, 0.0) || part_.locate(th) >= 0) return;
      }
      if (!solve_at(th)) {
        ++part_.stats.lps;
        if (!mpqp_feasible(p_, th)) return;  // stepped across the feasible set's boundary
        continue;
      }
      for (const std::vector<int>& act : candidates(th)) {
        if (seen_.count(act)) continue;  // a known region that just misses th: try the next
        detail::RegionBuild b = detail::build_region(p_, fac_, act, opt_.min_radius);
        part_.stats.lps += b.lps;
        if (b.outcome == detail::RegionOutcome::LowerDimensional) ++part_.stats.lower_dimensional;
        if (b.outcome != detail::RegionOutcome::Ok || !b.region.set.contains(th, 1e-7)) continue;
        seen_.insert(act);
        part_.regions.push_back(std::move(b.region));
        push_facets(part_.regions.back());
        return;
      }
    }
    ++part_.stats.unresolved_facets;
  }

  void push_facets(const CriticalRegion& r) {
    for (Eigen::Index i = 0; i < r.set.H.rows(); ++i) {
      if (r.boundary[static_cast<std::size_t>(i)]) continue;
      const ChebyshevBall fb = detail::facet_ball(r.set.H, r.set.k, static_cast<int>(i), p_.domain);
      ++part_.stats.lps;
      if (fb.radius <= 0.0) continue;
      const double step = std::min(opt_.step, 0.5 * fb.radius + 0.1 * opt_.step);
      queue_.push_back(fb.center + step * r.set.H.row(i).transpose());
    }
  }

  const MpQp& p_;
  MpQpOptions opt_;
  detail::MpQpFactors fac_;
  std::mt19937_64 rng_;
  Clock::time_point t0_;
  std::unique_ptr<QpSolver> oracle_;
  Eigen::VectorXd z_, y_;
  Partition part_;
  std::deque<Eigen::VectorXd> queue_;
  std::set<std::vector<int>> seen_;
};

}  // namespace

Partition solve_mpqp(const MpQp& p, const MpQpOptions& opt) {
  if (opt.max_regions < 1 || !(opt.time_limit_s > 0.0) || !(opt.min_radius > 0.0) || !(opt.step > 0.0) ||
      opt.coverage_samples < 1 || opt.coverage_passes < 1) {
    throw std::invalid_argument("mpQP options: max_regions >= 1, time_limit_s > 0, min_radius > 0, step > 0, "
                                "coverage_samples >= 1 and coverage_passes >= 1 are required");
  }
  return Explorer(p, opt).run();
}

}  // namespace tmpc
