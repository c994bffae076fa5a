// The offline synthesis pipeline (thesis ch. 3, DESIGN.md section 4), in normalized
// coordinates (x_n = N_x x, u_n = N_u u; weights transformed so the cost is unchanged):
//   error model -> W -> tube gains (LQR, Theorem 3.1 thesis / robust) -> RPI zonotope
//   -> tightened sets X_bar = X - Z, U_bar = U - K Z (Proposition 3.1) -> margin
//   -> QP data (3.50)-(3.55), LQR fallback, terminal cost.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tmpc/model/config.hpp"
#include "tmpc/model/error_model.hpp"
#include "tmpc/qp/mpc_qp.hpp"
#include "tmpc/sets/box.hpp"
#include "tmpc/sets/zonotope.hpp"
#include "tmpc/synthesis/estimator.hpp"
#include "tmpc/synthesis/lmi_gain.hpp"
#include "tmpc/synthesis/rpi.hpp"

namespace tmpc {

/// Sizes of a set's interval hull, thesis Tables 5.1 and 5.2.
struct SetSize {
  double one_norm_radius = 0.0;  ///< sum of the interval diameters
  double volume = 0.0;           ///< product of the interval diameters
};
SetSize set_size(const Box& b);

/// One tube gain and the tube it gives.
struct GainDesign {
  std::string name;                 ///< "lqr", "lmi_thesis", "lmi_robust"
  bool available = false;           ///< the gain exists (designed and checked)
  std::string message;              ///< why not, or the solver's verdict
  Eigen::MatrixXd K;                ///< u_n = K x_n
  std::vector<double> vertex_spectral_radius;  ///< nominal first, then the 8 vertices
  LmiGainResult lmi;                ///< LMI gains only
  double certified_w_scale = -1.0;  ///< robust form: largest W scale found feasible (-1: not searched)
  double refuted_w_scale = -1.0;    ///< robust form: smallest W scale found infeasible (-1: none)
  bool tube_ok = false;             ///< RPI computed and tightened sets non-empty
  std::string tube_message;
  int j = 0;
  double alpha = 0.0;
  int generators = 0;
  Box z_hull;                       ///< interval hull of Z (normalized)
  Box x_bar, u_bar;                 ///< tightened sets (normalized)
  double margin = 0.0;              ///< largest W scale with non-empty tightened sets
  double seconds = 0.0;
};

/// RPI variants of the selected gain side by side (thesis Tables 5.1, 5.2).
struct VariantComparison {
  std::string variant;
  bool ok = false;
  std::string message;
  int j = 0;
  double alpha = 0.0;
  SetSize z, x_bar, u_bar;
  double support_ratio = 0.0;       ///< worst h(S_i Z + W)/h(Z) over the vertices (<= 1: invariant)
};

struct ControllerDesign {
  Config cfg;
  std::string config_text;
  std::vector<std::string> state_names, input_names;
  EnvelopeSettings envelope;                   ///< resolved (a box, also from trajectories)
  ErrorModel em;
  Eigen::MatrixXd Sigma_rho_n, Sigma_lambda_n;  ///< weights in normalized coordinates
  Eigen::MatrixXd Sigma_delta_n;                 ///< input-rate weight, normalized (zero: none)
  std::vector<Eigen::MatrixXd> vertices;       ///< normalized A: nominal first, then the vertices (none: LTI)
  Zonotope W;                                  ///< normalized uncertainty set
  std::string w_description;
  Box X, U;                                    ///< constraint sets (normalized error coordinates)

  std::vector<GainDesign> gains;
  int selected = -1;                           ///< index into gains
  Eigen::MatrixXd K;                           ///< selected tube gain
  Eigen::MatrixXd K_lqr, P_lqr;                ///< fallback law and DARE solution
  Eigen::MatrixXd L_terminal;
  std::vector<Eigen::MatrixXd> K_vertices;     ///< per-vertex gains (Theorem 3.3)

  RpiResult tube;                              ///< the selected gain's tube (configured variant)
  SupportCheck support_check;                  ///< independent invariance check of `tube`
  std::vector<VariantComparison> variants;
  Box x_bar, u_bar;
  double margin = 0.0;
  std::string margin_method;
  MpcQpData qp;

  /// State estimation (config `estimation`): the Kalman filter (observer kalman) and,
  /// with output_feedback_tube, its tube, which then replaces the state tube: `tube.Z`
  /// is Z_c and x_bar, u_bar are X - (Z_c + E_x), U - K Z_c (estimator.hpp).
  bool kalman = false;
  KalmanDesign kf;
  /// The noise trade-off of the LQR tube gain (with the filter): the input standard
  /// deviation the estimation error passes through K (sqrt diag K Sigma K', Sigma the
  /// filter's a-posteriori covariance; physical units), against the tube's robustness
  /// margin, for the configured input weights scaled by each factor (1: the design's).
  struct NoiseTradeoff {
    double scale = 1.0;
    Eigen::VectorXd input_noise_std;
    double spectral_radius = 0.0, margin = 0.0;
  };
  std::vector<NoiseTradeoff> noise_tradeoff;
  bool output_feedback = false;  ///< the output-feedback tube is applied
  bool of_computed = false;      ///< ... and computed (always with the filter, for the report)
  std::string of_message;        ///< why it could not be computed (not applied: reported only)
  OutputFeedbackTube of;
  Box x_bar_state_feedback, u_bar_state_feedback;  ///< the state tube's sets, for the report

  struct Timing {
    double error_model = 0, uncertainty = 0, gains = 0, rpi = 0, checks = 0, estimation = 0, qp = 0, total = 0;
  } seconds;
};

/// Progress messages ("designing the LMI gain ...") for long steps; may be empty.
using DesignProgress = std::function<void(const std::string&)>;

/// Run the whole synthesis. Throws std::runtime_error with a clear message when the
/// selected gain does not exist or a tightened set is empty (naming the dimension).
ControllerDesign design_controller(const Config& cfg, const std::string& config_text,
                                   const DesignProgress& progress = {});

/// The JSON report (stable keys) of a design.
std::string design_report_json(const ControllerDesign& d);

}  // namespace tmpc
