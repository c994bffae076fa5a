// Dense LPs through CLP's ClpSimplex (dual simplex, no output).
#include "tmpc/sets/lp.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <ClpSimplex.hpp>

namespace tmpc {

const char* to_string(LpStatus s) {
  switch (s) {
    case LpStatus::Optimal: return "optimal";
    case LpStatus::Infeasible: return "infeasible";
    case LpStatus::Unbounded: return "unbounded";
    case LpStatus::Failed: return "failed";
  }
  return "?";
}

namespace {

// Load min c'x s.t. A x <= b, Aeq x = beq, lo <= x <= hi into a CLP model (column-major).
void load(ClpSimplex& model, const Eigen::VectorXd& c, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
          const Eigen::MatrixXd& Aeq, const Eigen::VectorXd& beq, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
  const int n = static_cast<int>(c.size());
  const int mi = static_cast<int>(A.rows()), me = static_cast<int>(Aeq.rows());
  const int m = mi + me;
  std::vector<CoinBigIndex> start(static_cast<std::size_t>(n) + 1);
  std::vector<int> index;
  std::vector<double> value;
  index.reserve(static_cast<std::size_t>(m) * static_cast<std::size_t>(n));
  value.reserve(index.capacity());
  for (int j = 0; j < n; ++j) {
    start[static_cast<std::size_t>(j)] = static_cast<CoinBigIndex>(index.size());
    for (int i = 0; i < mi; ++i) {
      if (A(i, j) != 0.0) {
        index.push_back(i);
        value.push_back(A(i, j));
      }
    }
    for (int i = 0; i < me; ++i) {
      if (Aeq(i, j) != 0.0) {
        index.push_back(mi + i);
        value.push_back(Aeq(i, j));
      }
    }
  }
  start[static_cast<std::size_t>(n)] = static_cast<CoinBigIndex>(index.size());
  const double inf = COIN_DBL_MAX;
  std::vector<double> rlo(static_cast<std::size_t>(m)), rhi(static_cast<std::size_t>(m)), clo(static_cast<std::size_t>(n)),
      chi(static_cast<std::size_t>(n));
  for (int i = 0; i < mi; ++i) {
    rlo[static_cast<std::size_t>(i)] = -inf;
    rhi[static_cast<std::size_t>(i)] = std::isfinite(b(i)) ? b(i) : inf;  // +infinity: no row
  }
  for (int i = 0; i < me; ++i) rlo[static_cast<std::size_t>(mi + i)] = rhi[static_cast<std::size_t>(mi + i)] = beq(i);
  for (int j = 0; j < n; ++j) {
    clo[static_cast<std::size_t>(j)] = std::isfinite(lo(j)) ? lo(j) : -inf;
    chi[static_cast<std::size_t>(j)] = std::isfinite(hi(j)) ? hi(j) : inf;
  }
  model.setLogLevel(0);
  model.loadProblem(n, m, start.data(), index.data(), value.data(), clo.data(), chi.data(), c.data(), rlo.data(),
                    rhi.data());
  model.setOptimizationDirection(1.0);
  // No scaling: callers pass normalized rows, and CLP's scaled dual simplex stopped
  // "optimal" at wrong vertices on the 24-dimensional region LPs (secondary status 3).
  model.scaling(0);
}

LpResult result(ClpSimplex& model, const Eigen::VectorXd& c) {
  LpResult r;
  if (model.status() == 0 && model.secondaryStatus() != 0) return r;
  switch (model.status()) {
    case 0: r.status = LpStatus::Optimal; break;
    case 1: r.status = LpStatus::Infeasible; break;
    case 2: r.status = LpStatus::Unbounded; break;
    default: r.status = LpStatus::Failed; break;
  }
  if (r.status == LpStatus::Optimal) {
    r.x = Eigen::Map<const Eigen::VectorXd>(model.primalColumnSolution(), c.size());
    r.value = c.dot(r.x);
  }
  return r;
}

}  // namespace

LpResult solve_lp(const Eigen::VectorXd& c, const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                  const Eigen::MatrixXd& Aeq, const Eigen::VectorXd& beq, const Eigen::VectorXd& lo,
                  const Eigen::VectorXd& hi) {
  ClpSimplex model;
  load(model, c, A, b, Aeq, beq, lo, hi);
  model.dual();
  if (model.status() == 0 && model.secondaryStatus() != 0) model.initialSolve();
  return result(model, c);
}

LpWorkspace::LpWorkspace(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                         const Eigen::VectorXd& hi)
    : model_(std::make_unique<ClpSimplex>()), n_(static_cast<int>(A.cols())) {
  load(*model_, Eigen::VectorXd::Zero(A.cols()), A, b, Eigen::MatrixXd(0, A.cols()), Eigen::VectorXd(0), lo, hi);
}
LpWorkspace::~LpWorkspace() = default;
LpWorkspace::LpWorkspace(LpWorkspace&&) noexcept = default;
LpWorkspace& LpWorkspace::operator=(LpWorkspace&&) noexcept = default;

LpResult LpWorkspace::minimize(const Eigen::VectorXd& c) {
  for (int j = 0; j < n_; ++j) model_->setObjectiveCoefficient(j, c(j));
  model_->primal();
  if (model_->status() == 0 && model_->secondaryStatus() != 0) model_->initialSolve();
  return result(*model_, c);
}

void LpWorkspace::set_rhs(int i, double v) { model_->setRowUpper(i, std::isfinite(v) ? v : COIN_DBL_MAX); }

double largest_common_slack(const Eigen::MatrixXd& A, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                            double cap) {
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::Index rows = A.rows(), n = A.cols();
  // max t  s.t.  A x + t <= hi,  -A x + t <= -lo,  t <= cap  (x free)
  Eigen::MatrixXd G(2 * rows, n + 1);
  Eigen::VectorXd b(2 * rows);
  G << A, Eigen::VectorXd::Ones(rows), -A, Eigen::VectorXd::Ones(rows);
  b << hi, -lo;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1), xlo = Eigen::VectorXd::Constant(n + 1, -inf),
                  xhi = Eigen::VectorXd::Constant(n + 1, inf);
  c(n) = -1.0;
  xhi(n) = cap;
  const LpResult lp = solve_lp(c, G, b, Eigen::MatrixXd(0, n + 1), Eigen::VectorXd(0), xlo, xhi);
  return lp.status == LpStatus::Optimal ? -lp.value : -inf;
}

ChebyshevBall chebyshev_ball(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& lo,
                             const Eigen::VectorXd& hi, double r_max) {
  const Eigen::Index n = A.cols(), m = A.rows();
  // Variables (x, r): max r s.t. a_i'x + |a_i| r <= b_i, lo + r <= x <= hi - r (finite bounds).
  int nb = 0;
  for (Eigen::Index j = 0; j < n; ++j) nb += std::isfinite(lo(j)) + std::isfinite(hi(j));
  Eigen::MatrixXd Ab = Eigen::MatrixXd::Zero(m + nb, n + 1);
  Eigen::VectorXd bb(m + nb);
  Ab.topLeftCorner(m, n) = A;
  Ab.col(n).head(m) = A.rowwise().norm();
  bb.head(m) = b;
  Eigen::Index k = m;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (std::isfinite(hi(j))) {
      Ab(k, j) = 1.0;
      Ab(k, n) = 1.0;
      bb(k++) = hi(j);
    }
    if (std::isfinite(lo(j))) {
      Ab(k, j) = -1.0;
      Ab(k, n) = 1.0;
      bb(k++) = -lo(j);
    }
  }
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1);
  c(n) = -1.0;
  Eigen::VectorXd xlo(n + 1), xhi(n + 1);
  xlo.head(n) = lo;
  xhi.head(n) = hi;
  xlo(n) = -std::numeric_limits<double>::infinity();
  xhi(n) = r_max;
  const LpResult r = solve_lp(c, Ab, bb, Eigen::MatrixXd(0, n + 1), Eigen::VectorXd(0), xlo, xhi);
  ChebyshevBall ball;
  if (r.status != LpStatus::Optimal) return ball;
  ball.center = r.x.head(n);
  ball.radius = r.x(n);
  return ball;
}

}  // namespace tmpc
