// A small LMI modelling layer over an SDP solver (CSDP).
//
// Decision variables y (scalars, symmetric matrices, full matrices) enter affine
// matrix expressions F(y) = F_0 + sum_v y_v F_v. A problem is
//     minimize c'y  subject to  F_b(y) >= 0 (positive semidefinite), b = 1..B
// and maps to CSDP's dual form  min a'y  s.t.  sum_v y_v A_v - C = Z >= 0  with
// A_v = blkdiag(F_{b,v}), C = -blkdiag(F_{b,0}), a = c.
// Strict inequalities are written with an explicit margin (F >= eps I).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tmpc {

/// Affine matrix expression M(y) = M0 + sum_v y_v M_v with sparse M_v.
class AffineMatrix {
 public:
  struct Entry {
    int i, j;
    double v;
  };

  AffineMatrix() = default;
  AffineMatrix(int rows, int cols);
  static AffineMatrix constant(const Eigen::MatrixXd& m);
  static AffineMatrix zero(int rows, int cols) { return AffineMatrix(rows, cols); }

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  const Eigen::MatrixXd& constant_part() const { return constant_; }
  const std::map<int, std::vector<Entry>>& terms() const { return terms_; }

  void add_term(int var, int i, int j, double v);
  /// Value at y.
  Eigen::MatrixXd value(const Eigen::VectorXd& y) const;

  AffineMatrix transpose() const;
  AffineMatrix operator+(const AffineMatrix& o) const;
  AffineMatrix operator-(const AffineMatrix& o) const;
  AffineMatrix operator*(double s) const;
  friend AffineMatrix operator*(const Eigen::MatrixXd& a, const AffineMatrix& x);
  AffineMatrix operator*(const Eigen::MatrixXd& b) const;

 private:
  int rows_ = 0, cols_ = 0;
  Eigen::MatrixXd constant_;
  std::map<int, std::vector<Entry>> terms_;  // merged, one entry per (i, j)
  void compact();
  friend class LmiProblem;
};

/// Outcome of an SDP solve, from the solver's own return code.
enum class SdpStatus {
  Solved,               // CSDP 0
  PrimalInfeasible,     // CSDP 1: its primal, i.e. our problem is unbounded
  Infeasible,           // CSDP 2: its dual, i.e. our LMIs are infeasible
  PartialSuccess,       // CSDP 3: solved to reduced accuracy
  MaxIterations,        // CSDP 4
  NumericalFailure,     // CSDP 5-9
};
const char* to_string(SdpStatus s);

struct SdpResult {
  SdpStatus status = SdpStatus::NumericalFailure;
  int solver_code = -1;
  std::string message;   // solver's verdict line(s)
  std::string log;       // full solver output
  Eigen::VectorXd y;
  double primal_objective = 0.0;
  double dual_objective = 0.0;
  double seconds = 0.0;
  bool usable() const { return status == SdpStatus::Solved || status == SdpStatus::PartialSuccess; }
};

class LmiProblem {
 public:
  /// New scalar variable; returns its index.
  int add_scalar();
  /// New symmetric n x n matrix variable (n(n+1)/2 scalars) as an expression.
  AffineMatrix add_symmetric(int n);
  /// New rows x cols matrix variable as an expression.
  AffineMatrix add_matrix(int rows, int cols);
  AffineMatrix scalar_expr(int var) const;

  /// Require F >= 0 (F symmetric; only its lower triangle is read).
  void require_psd(const AffineMatrix& f, const std::string& name);
  /// Assemble a symmetric block matrix from its lower-triangular blocks
  /// (blocks[r][c] for c <= r; empty rows() == 0 means a zero block).
  static AffineMatrix symmetric_blocks(const std::vector<std::vector<AffineMatrix>>& lower);

  void set_objective(int var, double coeff);

  int variables() const { return nvars_; }
  int blocks() const { return static_cast<int>(blocks_.size()); }
  const std::vector<std::string>& block_names() const { return names_; }

  /// Solve with CSDP; the solver's console output is captured into the result.
  SdpResult solve() const;

  /// Smallest eigenvalue of each constraint block at y (independent check).
  std::vector<double> block_min_eigenvalues(const Eigen::VectorXd& y) const;

 private:
  int nvars_ = 0;
  std::vector<AffineMatrix> blocks_;
  std::vector<std::string> names_;
  std::map<int, double> objective_;
};

}  // namespace tmpc
