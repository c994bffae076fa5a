// LMI modelling layer and the CSDP backend.
#include "tmpc/synthesis/lmi.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <unistd.h>
#include <unordered_map>

#include <Eigen/Eigenvalues>

extern "C" {
#include <csdp/declarations.h>
}

namespace tmpc {

// ---------------------------------------------------------------------------
// AffineMatrix
// ---------------------------------------------------------------------------

AffineMatrix::AffineMatrix(int rows, int cols) : rows_(rows), cols_(cols), constant_(Eigen::MatrixXd::Zero(rows, cols)) {}

AffineMatrix AffineMatrix::constant(const Eigen::MatrixXd& m) {
  AffineMatrix a(static_cast<int>(m.rows()), static_cast<int>(m.cols()));
  a.constant_ = m;
  return a;
}

void AffineMatrix::add_term(int var, int i, int j, double v) {
  if (i < 0 || i >= rows_ || j < 0 || j >= cols_) throw std::out_of_range("AffineMatrix::add_term: index out of range");
  terms_[var].push_back({i, j, v});
}

void AffineMatrix::compact() {
  for (auto it = terms_.begin(); it != terms_.end();) {
    std::unordered_map<long, double> acc;
    for (const Entry& e : it->second) acc[static_cast<long>(e.i) * cols_ + e.j] += e.v;
    std::vector<Entry> out;
    out.reserve(acc.size());
    for (const auto& kv : acc) {
      if (kv.second != 0.0) out.push_back({static_cast<int>(kv.first / cols_), static_cast<int>(kv.first % cols_), kv.second});
    }
    if (out.empty()) {
      it = terms_.erase(it);
    } else {
      it->second = std::move(out);
      ++it;
    }
  }
}

Eigen::MatrixXd AffineMatrix::value(const Eigen::VectorXd& y) const {
  Eigen::MatrixXd m = constant_;
  for (const auto& [var, entries] : terms_) {
    for (const Entry& e : entries) m(e.i, e.j) += y(var) * e.v;
  }
  return m;
}

AffineMatrix AffineMatrix::transpose() const {
  AffineMatrix t(cols_, rows_);
  t.constant_ = constant_.transpose();
  for (const auto& [var, entries] : terms_) {
    auto& out = t.terms_[var];
    out.reserve(entries.size());
    for (const Entry& e : entries) out.push_back({e.j, e.i, e.v});
  }
  return t;
}

AffineMatrix AffineMatrix::operator+(const AffineMatrix& o) const {
  if (o.rows_ != rows_ || o.cols_ != cols_) {
    throw std::invalid_argument("AffineMatrix +: " + std::to_string(rows_) + "x" + std::to_string(cols_) + " vs " +
                                std::to_string(o.rows_) + "x" + std::to_string(o.cols_));
  }
  AffineMatrix s = *this;
  s.constant_ += o.constant_;
  for (const auto& [var, entries] : o.terms_) {
    auto& out = s.terms_[var];
    out.insert(out.end(), entries.begin(), entries.end());
  }
  s.compact();
  return s;
}

AffineMatrix AffineMatrix::operator*(double k) const {
  AffineMatrix s = *this;
  s.constant_ *= k;
  for (auto& [var, entries] : s.terms_) {
    for (Entry& e : entries) e.v *= k;
  }
  return s;
}

AffineMatrix AffineMatrix::operator-(const AffineMatrix& o) const { return *this + o * -1.0; }

AffineMatrix operator*(const Eigen::MatrixXd& a, const AffineMatrix& x) {
  if (a.cols() != x.rows_) {
    throw std::invalid_argument("AffineMatrix product: " + std::to_string(a.cols()) + " columns vs " +
                                std::to_string(x.rows_) + " rows");
  }
  AffineMatrix p(static_cast<int>(a.rows()), x.cols_);
  p.constant_ = a * x.constant_;
  for (const auto& [var, entries] : x.terms_) {
    auto& out = p.terms_[var];
    for (const AffineMatrix::Entry& e : entries) {
      for (int r = 0; r < a.rows(); ++r) {
        const double v = a(r, e.i) * e.v;
        if (v != 0.0) out.push_back({r, e.j, v});
      }
    }
  }
  p.compact();
  return p;
}

AffineMatrix AffineMatrix::operator*(const Eigen::MatrixXd& b) const {
  if (b.rows() != cols_) {
    throw std::invalid_argument("AffineMatrix product: " + std::to_string(cols_) + " columns vs " +
                                std::to_string(b.rows()) + " rows");
  }
  AffineMatrix p(rows_, static_cast<int>(b.cols()));
  p.constant_ = constant_ * b;
  for (const auto& [var, entries] : terms_) {
    auto& out = p.terms_[var];
    for (const Entry& e : entries) {
      for (int c = 0; c < b.cols(); ++c) {
        const double v = e.v * b(e.j, c);
        if (v != 0.0) out.push_back({e.i, c, v});
      }
    }
  }
  p.compact();
  return p;
}

// ---------------------------------------------------------------------------
// LmiProblem
// ---------------------------------------------------------------------------

int LmiProblem::add_scalar() { return nvars_++; }

AffineMatrix LmiProblem::scalar_expr(int var) const {
  AffineMatrix a(1, 1);
  a.add_term(var, 0, 0, 1.0);
  return a;
}

AffineMatrix LmiProblem::add_symmetric(int n) {
  AffineMatrix a(n, n);
  for (int j = 0; j < n; ++j) {
    for (int i = j; i < n; ++i) {
      const int v = nvars_++;
      a.add_term(v, i, j, 1.0);
      if (i != j) a.add_term(v, j, i, 1.0);
    }
  }
  return a;
}

AffineMatrix LmiProblem::add_matrix(int rows, int cols) {
  AffineMatrix a(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) a.add_term(nvars_++, i, j, 1.0);
  }
  return a;
}

AffineMatrix LmiProblem::symmetric_blocks(const std::vector<std::vector<AffineMatrix>>& lower) {
  const std::size_t nb = lower.size();
  std::vector<int> size(nb), offset(nb + 1, 0);
  for (std::size_t r = 0; r < nb; ++r) {
    if (lower[r].size() != r + 1) throw std::invalid_argument("symmetric_blocks: row " + std::to_string(r) + " needs " + std::to_string(r + 1) + " blocks");
    size[r] = lower[r][r].rows();
    offset[r + 1] = offset[r] + size[r];
  }
  AffineMatrix out(offset[nb], offset[nb]);
  auto place = [&](const AffineMatrix& m, int r0, int c0, bool mirror) {
    out.constant_.block(r0, c0, m.rows(), m.cols()) = m.constant_;
    if (mirror) out.constant_.block(c0, r0, m.cols(), m.rows()) = m.constant_.transpose();
    for (const auto& [var, entries] : m.terms_) {
      auto& dst = out.terms_[var];
      for (const AffineMatrix::Entry& e : entries) {
        dst.push_back({r0 + e.i, c0 + e.j, e.v});
        if (mirror) dst.push_back({c0 + e.j, r0 + e.i, e.v});
      }
    }
  };
  for (std::size_t r = 0; r < nb; ++r) {
    for (std::size_t c = 0; c <= r; ++c) {
      const AffineMatrix& m = lower[r][c];
      if (m.rows() == 0 && m.cols() == 0) continue;  // zero block
      if (m.rows() != size[r] || m.cols() != size[c]) {
        throw std::invalid_argument("symmetric_blocks: block (" + std::to_string(r) + "," + std::to_string(c) +
                                    ") is " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
                                    ", expected " + std::to_string(size[r]) + "x" + std::to_string(size[c]));
      }
      place(m, offset[r], offset[c], r != c);
    }
  }
  out.compact();
  return out;
}

void LmiProblem::require_psd(const AffineMatrix& f, const std::string& name) {
  if (f.rows() != f.cols()) throw std::invalid_argument("LMI '" + name + "' is not square");
  blocks_.push_back(f);
  names_.push_back(name);
}

void LmiProblem::set_objective(int var, double coeff) { objective_[var] = coeff; }

std::vector<double> LmiProblem::block_min_eigenvalues(const Eigen::VectorXd& y) const {
  std::vector<double> out;
  for (const AffineMatrix& b : blocks_) {
    Eigen::MatrixXd m = b.value(y);
    m = 0.5 * (m + m.transpose());
    out.push_back(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m, Eigen::EigenvaluesOnly).eigenvalues().minCoeff());
  }
  return out;
}

const char* to_string(SdpStatus s) {
  switch (s) {
    case SdpStatus::Solved: return "solved";
    case SdpStatus::PrimalInfeasible: return "unbounded (CSDP: primal infeasible)";
    case SdpStatus::Infeasible: return "infeasible (CSDP: dual infeasible)";
    case SdpStatus::PartialSuccess: return "solved to reduced accuracy";
    case SdpStatus::MaxIterations: return "iteration limit";
    case SdpStatus::NumericalFailure: return "numerical failure";
  }
  return "?";
}

namespace {

/// Redirects stdout (CSDP prints there) into a temporary file while alive.
class StdoutCapture {
 public:
  StdoutCapture() {
    std::fflush(stdout);
    char name[] = "/tmp/tmpc-csdp-XXXXXX";
    fd_ = mkstemp(name);
    if (fd_ < 0) return;
    unlink(name);
    saved_ = dup(STDOUT_FILENO);
    dup2(fd_, STDOUT_FILENO);
  }
  std::string finish() {
    if (fd_ < 0) return "";
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
    std::string out;
    lseek(fd_, 0, SEEK_SET);
    char buf[4096];
    ssize_t n;
    while ((n = read(fd_, buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
    close(fd_);
    fd_ = -1;
    return out;
  }
  ~StdoutCapture() { finish(); }

 private:
  int fd_ = -1;
  int saved_ = -1;
};

std::mutex csdp_mutex;  // CSDP keeps global state and we redirect stdout

template <class T>
T* cmalloc(std::size_t n) {
  void* p = std::calloc(n, sizeof(T));
  if (p == nullptr) throw std::bad_alloc();
  return static_cast<T*>(p);
}

}  // namespace

SdpResult LmiProblem::solve() const {
  SdpResult res;
  const int k = nvars_;
  const int nb = static_cast<int>(blocks_.size());
  if (k == 0 || nb == 0) throw std::invalid_argument("LmiProblem::solve: no variables or no constraints");
  int n = 0;
  for (const AffineMatrix& b : blocks_) n += b.rows();

  // C = -blkdiag(F_b0), 1-based blocks, Fortran-ordered dense matrices.
  struct blockmatrix C;
  C.nblocks = nb;
  C.blocks = cmalloc<struct blockrec>(static_cast<std::size_t>(nb) + 1);
  for (int b = 1; b <= nb; ++b) {
    const AffineMatrix& f = blocks_[static_cast<std::size_t>(b - 1)];
    const int s = f.rows();
    C.blocks[b].blocksize = s;
    C.blocks[b].blockcategory = MATRIX;
    C.blocks[b].data.mat = cmalloc<double>(static_cast<std::size_t>(s) * s);
    for (int j = 1; j <= s; ++j) {
      for (int i = 1; i <= s; ++i) C.blocks[b].data.mat[ijtok(i, j, s)] = -0.5 * (f.constant_part()(i - 1, j - 1) + f.constant_part()(j - 1, i - 1));
    }
  }
  double* a = cmalloc<double>(static_cast<std::size_t>(k) + 1);
  for (const auto& [var, coeff] : objective_) a[var + 1] = coeff;

  // Constraint matrices A_v = blkdiag(F_bv): upper-triangular entries, blocks in order.
  struct constraintmatrix* constraints = cmalloc<struct constraintmatrix>(static_cast<std::size_t>(k) + 1);
  std::vector<struct sparseblock*> tail(static_cast<std::size_t>(k) + 1, nullptr);
  std::vector<int> used(static_cast<std::size_t>(k), 0);
  for (int b = 1; b <= nb; ++b) {
    const AffineMatrix& f = blocks_[static_cast<std::size_t>(b - 1)];
    for (const auto& [var, entries] : f.terms()) {
      std::vector<AffineMatrix::Entry> upper;
      for (const AffineMatrix::Entry& e : entries) {
        if (e.i <= e.j) upper.push_back(e);
      }
      if (upper.empty()) continue;
      auto* blk = cmalloc<struct sparseblock>(1);
      blk->blocknum = b;
      blk->blocksize = f.rows();
      blk->constraintnum = var + 1;
      blk->numentries = static_cast<int>(upper.size());
      blk->entries = cmalloc<double>(upper.size() + 1);
      blk->iindices = cmalloc<int>(upper.size() + 1);
      blk->jindices = cmalloc<int>(upper.size() + 1);
      for (std::size_t t = 0; t < upper.size(); ++t) {
        blk->iindices[t + 1] = upper[t].i + 1;
        blk->jindices[t + 1] = upper[t].j + 1;
        blk->entries[t + 1] = upper[t].v;
      }
      auto& last = tail[static_cast<std::size_t>(var + 1)];
      if (last == nullptr) {
        constraints[var + 1].blocks = blk;
      } else {
        last->next = blk;
      }
      last = blk;
      used[static_cast<std::size_t>(var)] = 1;
    }
  }
  for (int v = 0; v < k; ++v) {
    if (!used[static_cast<std::size_t>(v)]) {
      free_prob(n, k, C, a, constraints, {0, nullptr}, nullptr, {0, nullptr});
      throw std::invalid_argument("LmiProblem::solve: variable " + std::to_string(v) + " appears in no constraint");
    }
  }

  struct blockmatrix X, Z;
  double* y = nullptr;
  double pobj = 0.0, dobj = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  {
    std::lock_guard<std::mutex> lock(csdp_mutex);
    StdoutCapture capture;
    initsoln(n, k, C, a, constraints, &X, &y, &Z);
    res.solver_code = easy_sdp(n, k, C, a, constraints, 0.0, &X, &y, &Z, &pobj, &dobj);
    res.log = capture.finish();
  }
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // CSDP reports the objectives of its own (maximization) primal; ours is min a'y.
  res.primal_objective = dobj;
  res.dual_objective = pobj;
  res.y = Eigen::VectorXd(k);
  for (int v = 0; v < k; ++v) res.y(v) = y[v + 1];
  free_prob(n, k, C, a, constraints, X, y, Z);

  switch (res.solver_code) {
    case 0: res.status = SdpStatus::Solved; break;
    case 1: res.status = SdpStatus::PrimalInfeasible; break;
    case 2: res.status = SdpStatus::Infeasible; break;
    case 3: res.status = SdpStatus::PartialSuccess; break;
    case 4: res.status = SdpStatus::MaxIterations; break;
    default: res.status = SdpStatus::NumericalFailure; break;
  }
  // The solver's verdict: its lines that are not iteration records.
  std::istringstream lines(res.log);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("Iter:", 0) == 0 || line.empty()) continue;
    res.message += (res.message.empty() ? "" : "; ") + line;
  }
  if (res.message.empty()) res.message = std::string("CSDP return code ") + std::to_string(res.solver_code);
  return res;
}

}  // namespace tmpc
