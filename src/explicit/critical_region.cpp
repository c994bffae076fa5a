// Critical regions: affine laws (4.9)-(4.12), region inequalities (4.13), redundancy removal.
#include "critical_region.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "tmpc/sets/lp.hpp"

namespace tmpc::detail {

namespace {
constexpr double kZeroRow = 1e-11;   // a row with a smaller norm is a pure constant
constexpr double kRedundant = 1e-9;  // slack tolerance of redundancy tests
}  // namespace

MpQpFactors::MpQpFactors(const MpQp& p) : llt(p.H) {
  HinvGt = llt.solve(p.G.transpose());
  HinvF = llt.solve(p.F);
  Hinvf = llt.solve(p.f);
}

std::vector<int> irredundant_rows(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Box& box,
                                  const std::vector<char>& box_row, int& lps) {
  const Eigen::Index n = A.cols();
  const Eigen::VectorXd c = box.center(), h = 0.5 * (box.hi - box.lo);
  // 1. Rows that the box alone satisfies (the box's own rows are kept for the LP test),
  // and duplicates (keep the tightest).
  std::vector<int> cand;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    if (box_row[static_cast<std::size_t>(i)]) {
      cand.push_back(static_cast<int>(i));
      continue;
    }
    const double box_max = A.row(i).dot(c) + A.row(i).cwiseAbs().dot(h);
    if (box_max > b(i) + kRedundant) cand.push_back(static_cast<int>(i));
  }
  std::sort(cand.begin(), cand.end(), [&](int i, int j) { return b(i) < b(j); });
  std::vector<int> uniq;
  for (int i : cand) {
    bool dup = false;
    for (int j : uniq) {
      if ((A.row(i) - A.row(j)).cwiseAbs().maxCoeff() < 1e-10) {
        dup = true;
        break;
      }
    }
    if (!dup) uniq.push_back(i);
  }
  // 2. LP test per row: max a_i'x over the other kept rows (row i relaxed by 1); the
  // box enters as rows, so the LP is bounded by them.
  std::vector<char> keep(uniq.size(), 1);
  Eigen::MatrixXd Ak(static_cast<Eigen::Index>(uniq.size()), n);
  Eigen::VectorXd bk(static_cast<Eigen::Index>(uniq.size()));
  for (std::size_t r = 0; r < uniq.size(); ++r) {
    Ak.row(static_cast<Eigen::Index>(r)) = A.row(uniq[r]);
    bk(static_cast<Eigen::Index>(r)) = b(uniq[r]);
  }
  const Eigen::VectorXd hi = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity()), lo = -hi;
  LpWorkspace lp_ws(Ak, bk, lo, hi);
  for (std::size_t r = 0; r < uniq.size(); ++r) {
    const auto ri = static_cast<Eigen::Index>(r);
    lp_ws.set_rhs(static_cast<int>(r), bk(ri) + 1.0);
    const LpResult lp = lp_ws.minimize(-Ak.row(ri).transpose());
    ++lps;
    if (lp.status == LpStatus::Optimal && -lp.value <= bk(ri) + kRedundant) {
      keep[r] = 0;
      lp_ws.set_rhs(static_cast<int>(r), std::numeric_limits<double>::infinity());
    } else {
      lp_ws.set_rhs(static_cast<int>(r), bk(ri));
    }
  }
  std::vector<int> out;
  for (std::size_t r = 0; r < uniq.size(); ++r) {
    if (keep[r]) out.push_back(uniq[r]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

ChebyshevBall facet_ball(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, int i, const Box& box) {
  const Eigen::Index n = A.cols(), m = A.rows();
  // Variables (x, r): max r  s.t. a_i'x = b_i,  a_j'x + r |a_j - (a_j'a_i) a_i| <= b_j.
  Eigen::MatrixXd Ai(m, n + 1);
  Eigen::VectorXd bi = b;
  const Eigen::RowVectorXd ai = A.row(i);
  for (Eigen::Index j = 0; j < m; ++j) {
    Ai.row(j).head(n) = A.row(j);
    Ai(j, n) = (A.row(j) - A.row(j).dot(ai) * ai).norm();
  }
  Ai(i, n) = 0.0;
  bi(i) = b(i) + 1.0;  // replaced by the equality
  Eigen::MatrixXd Aeq = Eigen::MatrixXd::Zero(1, n + 1);
  Aeq.row(0).head(n) = ai;
  Eigen::VectorXd beq = Eigen::VectorXd::Constant(1, b(i));
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1);
  c(n) = -1.0;
  Eigen::VectorXd lo(n + 1), hi(n + 1);
  lo.head(n) = box.lo;
  hi.head(n) = box.hi;
  lo(n) = 0.0;
  hi(n) = 1e3;
  const LpResult lp = solve_lp(c, Ai, bi, Aeq, beq, lo, hi);
  ChebyshevBall ball;
  if (lp.status != LpStatus::Optimal) return ball;
  ball.center = lp.x.head(n);
  ball.radius = lp.x(n);
  return ball;
}

RegionBuild build_region(const MpQp& p, const MpQpFactors& fac, const std::vector<int>& active, double min_radius) {
  RegionBuild out;
  const int nz = p.nz(), nt = p.ntheta();
  const auto na = static_cast<Eigen::Index>(active.size());
  const Eigen::Index ng = p.G.rows();
  Eigen::MatrixXd GA(na, nz), SA(na, nt), HinvGAt(nz, na);
  Eigen::VectorXd wA(na);
  for (Eigen::Index k = 0; k < na; ++k) {
    GA.row(k) = p.G.row(active[static_cast<std::size_t>(k)]);
    SA.row(k) = p.S.row(active[static_cast<std::size_t>(k)]);
    wA(k) = p.w(active[static_cast<std::size_t>(k)]);
    HinvGAt.col(k) = fac.HinvGt.col(active[static_cast<std::size_t>(k)]);
  }
  Eigen::MatrixXd Llam = Eigen::MatrixXd::Zero(na, nt);
  Eigen::VectorXd llam = Eigen::VectorXd::Zero(na);
  if (na > 0) {
    if (na > nz) {
      out.outcome = RegionOutcome::Licq;
      return out;
    }
    const Eigen::MatrixXd Mmat = GA * HinvGAt;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Mmat);
    lu.setThreshold(1e-10);
    if (lu.rank() < na) {
      out.outcome = RegionOutcome::Licq;
      return out;
    }
    Llam = -lu.solve(SA + GA * fac.HinvF);
    llam = -lu.solve(wA + GA * fac.Hinvf);
  }
  CriticalRegion& r = out.region;
  r.active = active;
  r.Kz = -(fac.HinvF + HinvGAt * Llam);
  r.kz = -(fac.Hinvf + HinvGAt * llam);
  // Rows: inactive primal constraints, multiplier signs, extra parameter constraints, the box.
  std::vector<char> is_active(static_cast<std::size_t>(ng), 0);
  for (int a : active) is_active[static_cast<std::size_t>(a)] = 1;
  const Eigen::Index rows = (ng - na) + na + p.T.rows() + 2 * nt;
  Eigen::MatrixXd A(rows, nt);
  Eigen::VectorXd b(rows);
  std::vector<char> boundary(static_cast<std::size_t>(rows), 0);
  Eigen::Index k = 0;
  const Eigen::MatrixXd GK = p.G * r.Kz - p.S;
  const Eigen::VectorXd gk = p.w - p.G * r.kz;
  for (Eigen::Index i = 0; i < ng; ++i) {
    if (is_active[static_cast<std::size_t>(i)]) continue;
    A.row(k) = GK.row(i);
    b(k++) = gk(i);
  }
  for (Eigen::Index i = 0; i < na; ++i) {
    A.row(k) = -Llam.row(i);
    b(k++) = llam(i);
  }
  for (Eigen::Index i = 0; i < p.T.rows(); ++i) {
    A.row(k) = p.T.row(i);
    boundary[static_cast<std::size_t>(k)] = 1;
    b(k++) = p.t(i);
  }
  for (int j = 0; j < nt; ++j) {
    A.row(k).setZero();
    A(k, j) = 1.0;
    boundary[static_cast<std::size_t>(k)] = 1;
    b(k++) = p.domain.hi(j);
    A.row(k).setZero();
    A(k, j) = -1.0;
    boundary[static_cast<std::size_t>(k)] = 1;
    b(k++) = -p.domain.lo(j);
  }
  // Normalize; constant rows either hold everywhere or make the region empty.
  std::vector<int> live;
  for (Eigen::Index i = 0; i < rows; ++i) {
    const double nrm = A.row(i).norm();
    if (nrm < kZeroRow) {
      if (b(i) < -1e-9) {
        out.outcome = RegionOutcome::Empty;
        return out;
      }
      continue;
    }
    A.row(i) /= nrm;
    b(i) /= nrm;
    live.push_back(static_cast<int>(i));
  }
  Eigen::MatrixXd Al(static_cast<Eigen::Index>(live.size()), nt);
  Eigen::VectorXd bl(static_cast<Eigen::Index>(live.size()));
  for (std::size_t q = 0; q < live.size(); ++q) {
    Al.row(static_cast<Eigen::Index>(q)) = A.row(live[q]);
    bl(static_cast<Eigen::Index>(q)) = b(live[q]);
  }
  const ChebyshevBall ball = chebyshev_ball(Al, bl, p.domain.lo, p.domain.hi);
  ++out.lps;
  if (ball.radius < 0.0) {
    out.outcome = RegionOutcome::Empty;
    return out;
  }
  if (ball.radius < min_radius) {
    out.outcome = RegionOutcome::LowerDimensional;
    return out;
  }
  std::vector<char> box_row(live.size());
  for (std::size_t q = 0; q < live.size(); ++q) box_row[q] = boundary[static_cast<std::size_t>(live[q])];
  const std::vector<int> kept = irredundant_rows(Al, bl, p.domain, box_row, out.lps);
  r.set.H.resize(static_cast<Eigen::Index>(kept.size()), nt);
  r.set.k.resize(static_cast<Eigen::Index>(kept.size()));
  for (std::size_t q = 0; q < kept.size(); ++q) {
    r.set.H.row(static_cast<Eigen::Index>(q)) = Al.row(kept[q]);
    r.set.k(static_cast<Eigen::Index>(q)) = bl(kept[q]);
    r.boundary.push_back(boundary[static_cast<std::size_t>(live[static_cast<std::size_t>(kept[q])])]);
  }
  r.center = ball.center;
  r.radius = ball.radius;
  out.outcome = RegionOutcome::Ok;
  return out;
}

}  // namespace tmpc::detail
