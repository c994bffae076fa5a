// What a controller artifact must mean before anything runs (artifact.hpp,
// check_artifact()): the record container proved the bytes are the ones written;
// these checks prove the records are a controller this build can fly.
#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "tmpc/model/equilibrium.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/synthesis/artifact.hpp"
#include "tmpc/synthesis/lqr.hpp"

namespace tmpc {

namespace {

class Checker {
 public:
  explicit Checker(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(const std::string& record, const std::string& what) const {
    throw ArtifactError(source_ + ": record '" + record + "': " + what);
  }
  static std::string num(double v) {
    std::ostringstream os;
    os.precision(6);
    os << v;
    return os.str();
  }
  void positive(const std::string& record, const Eigen::VectorXd& v) const {
    for (Eigen::Index i = 0; i < v.size(); ++i) {
      if (!(v(i) > 0.0)) fail(record, "entry " + std::to_string(i) + " is " + num(v(i)) + ", a scaling must be positive");
    }
  }
  void box(const std::string& record, const Box& b) const {
    const int e = b.first_empty_dimension();
    if (e >= 0) {
      fail(record + "_lo", "the set is empty in dimension " + std::to_string(e) + " (lo " + num(b.lo(e)) + " > hi " +
                               num(b.hi(e)) + ")");
    }
  }
  void inside(const std::string& record, const Box& inner, const Box& outer, const std::string& outer_name) const {
    for (int i = 0; i < inner.dim(); ++i) {
      if (inner.lo(i) < outer.lo(i) - 1e-12 || inner.hi(i) > outer.hi(i) + 1e-12) {
        fail(record + "_lo", "dimension " + std::to_string(i) + " [" + num(inner.lo(i)) + ", " + num(inner.hi(i)) +
                                 "] is not inside " + outer_name + " [" + num(outer.lo(i)) + ", " + num(outer.hi(i)) +
                                 "]: a tightened set lies inside its constraint set");
      }
    }
  }
  void symmetric_psd(const std::string& record, const Eigen::MatrixXd& m, bool definite) const {
    const double scale = std::max(1.0, m.cwiseAbs().maxCoeff());
    if ((m - m.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) fail(record, "is not symmetric");
    const double lmin = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (m + m.transpose())).eigenvalues().minCoeff();
    if (definite ? !(lmin > 0.0) : lmin < -1e-9 * scale) {
      fail(record, std::string("smallest eigenvalue ") + num(lmin) + ": a cost weight must be positive " +
                       (definite ? "definite" : "semidefinite"));
    }
  }
  void stabilizing(const std::string& record, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                   const Eigen::MatrixXd& K, const std::string& model) const {
    const double rho = spectral_radius(A + B * K);
    if (!(rho < 1.0)) {
      fail(record, "does not stabilize the " + model + " (spectral radius of A + B K = " + num(rho) + ", must be < 1)");
    }
  }
  void near(const std::string& record, double stored, double expected, double tol, const std::string& why) const {
    if (!(std::abs(stored - expected) <= tol * std::max(1.0, std::abs(expected)))) {
      fail(record, "is " + num(stored) + ", the embedded configuration gives " + num(expected) + " (" + why + ")");
    }
  }

 private:
  const std::string& source_;
};

}  // namespace

void check_artifact(const ControllerArtifact& a, const std::string& source) {
  const Checker c(source);
  // Dimensions this build's runtime supports, and every record consistent with them.
  if (a.n != kNa) c.fail("n", "is " + std::to_string(a.n) + ": this build's tiltrotor runtime flies " + std::to_string(kNa) + " error states");
  if (a.m != kNu) c.fail("m", "is " + std::to_string(a.m) + ": this build's tiltrotor runtime has " + std::to_string(kNu) + " inputs");
  if (a.D.cols() != kNd) c.fail("D", "has " + std::to_string(a.D.cols()) + " columns, the load force has " + std::to_string(kNd));
  if (a.N < 1 || a.N > kMaxHorizon) c.fail("N", "is " + std::to_string(a.N) + ", must be in [1, " + std::to_string(kMaxHorizon) + "]");
  if (a.M < 1 || a.M > a.N) c.fail("M", "is " + std::to_string(a.M) + ", must be in [1, N = " + std::to_string(a.N) + "]");
  if (!(a.sample_time >= 1e-5 && a.sample_time <= 1.0)) c.fail("sample_time", "is " + Checker::num(a.sample_time) + " s, must be in [1e-5, 1] s");
  if (a.A_vertices.size() > 64) c.fail("vertices", "is " + std::to_string(a.A_vertices.size()) + ", at most 64");
  c.positive("N_x", a.N_x);
  c.positive("N_u", a.N_u);
  // Sets: non-empty, the tightened ones inside theirs, the tube and W of the right size.
  c.box("X", a.X);
  c.box("U", a.U);
  c.box("x_bar", a.x_bar);
  c.box("u_bar", a.u_bar);
  c.inside("x_bar", a.x_bar, a.X, "X");
  c.inside("u_bar", a.u_bar, a.U, "U");
  if (a.Z.order() < 1) c.fail("Z_G", "the tube has no generator");
  if (!(a.margin >= 1.0 - 1e-9)) c.fail("margin", "is " + Checker::num(a.margin) + ": the design's own W must fit (margin >= 1)");
  // The cost is convex and the laws stabilize.
  c.symmetric_psd("Sigma_rho", a.Sigma_rho, false);
  c.symmetric_psd("Sigma_lambda", a.Sigma_lambda, true);
  c.symmetric_psd("L", a.L, false);
  c.symmetric_psd("P_lqr", a.P_lqr, true);
  const MpcQpData qp = a.qp();
  if (Eigen::LLT<Eigen::MatrixXd>(qp.H).info() != Eigen::Success) {
    c.fail("Sigma_lambda", "the QP Hessian H = 2 (P'W_x P + W_u) is not positive definite: the cost is not strictly convex");
  }
  c.stabilizing("K", a.A, a.B, a.K, "nominal model");
  for (std::size_t i = 0; i < a.A_vertices.size(); ++i) {
    c.stabilizing("K", a.A_vertices[i], a.B, a.K, "LPV vertex " + std::to_string(i));
  }
  c.stabilizing("K_lqr", a.A, a.B, a.K_lqr, "nominal model (LQR fallback)");
  // The embedded configuration: valid, and the records are the design it describes.
  Config cfg;
  try {
    cfg = load_config_from_string(a.config_text, source + " (embedded configuration)");
  } catch (const ConfigError& e) {
    c.fail("config", std::string("the embedded configuration is invalid: ") + e.what());
  }
  c.near("sample_time", a.sample_time, cfg.sample_time, 1e-12, "sample_time");
  if (a.N != cfg.synthesis.horizon) c.fail("N", "is " + std::to_string(a.N) + ", the embedded configuration's synthesis.horizon is " + std::to_string(cfg.synthesis.horizon));
  if (a.M != cfg.synthesis.control_horizon) c.fail("M", "is " + std::to_string(a.M) + ", the embedded configuration's synthesis.control_horizon is " + std::to_string(cfg.synthesis.control_horizon));
  if (a.tube_gain != cfg.synthesis.tube_gain) c.fail("tube_gain", "is '" + a.tube_gain + "', the embedded configuration's synthesis.tube_gain is '" + cfg.synthesis.tube_gain + "'");
  if (a.rpi_variant != cfg.synthesis.rpi_variant) c.fail("rpi_variant", "is '" + a.rpi_variant + "', the embedded configuration's synthesis.rpi.variant is '" + cfg.synthesis.rpi_variant + "'");
  if (a.terminal_cost != cfg.synthesis.terminal_cost) c.fail("terminal_cost", "is '" + a.terminal_cost + "', the embedded configuration's synthesis.terminal_cost is '" + cfg.synthesis.terminal_cost + "'");
  for (int i = 0; i < kNa; ++i) {
    c.near("N_x", a.N_x(i), 1.0 / cfg.state_error_max(i), 1e-12, "1 / constraints.state_error_max[" + std::to_string(i) + "]");
  }
  for (int i = 0; i < kNu; ++i) {
    c.near("N_u", a.N_u(i), 2.0 / (cfg.input_max(i) - cfg.input_min(i)), 1e-12,
           "2 / (input_max - input_min)[" + std::to_string(i) + "]");
  }
  // The vehicle: the hover equilibrium of the embedded parameters is the stored one
  // (a model edited after the design, e.g. a mass, changes it).
  const Equilibrium eq = solve_hover_equilibrium(TiltrotorModel(cfg.vehicle), cfg.reference.yaw);
  for (int i = 0; i < 4; ++i) c.near("u_eq", a.u_eq(i), eq.u(i), 1e-6, "the hover input of the embedded vehicle");
  for (int i = 0; i < 4; ++i) c.near("angles_eq", a.angles_eq(i), eq.angles(i), 1e-6, "the hover angles of the embedded vehicle");
}

}  // namespace tmpc
