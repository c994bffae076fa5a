// Plausibility gate of the measured state (DESIGN.md 5b): every state frame that the
// decoder accepted (finite, inside the absolute bounds, in session and sequence) is
// checked against the last frame the gate accepted before the controller sees it:
//   time: 0 < t - t_last and |t - t_last - k T_f| <= tol T_f,  k = sequence advance
//   jump: |e - e_pred|_i <= j_i (1 + (n - 1) / 10)  per measured state i, n = round((t - t_last) / T_f),
//         e_pred = A^n e_last + (A^(n-1) + ... + I) B u~   (normalized error model,
//         the input u~ = u - u_r applied since the last accepted frame, held)
// with e the measured error state (physical, yaw differences wrapped) and j_i the jump
// threshold of i's group. After more than `horizon` periods the jump test is skipped.
// A frame that fails is counted (Reject::Time, Reject::Jump) and treated as missing.
// A real jump (an estimator reset, a repositioned vehicle) must not lock the gate
// out: `resync_frames` consecutive rejected frames that pass both tests against each
// other are adopted as the new track (counted in resyncs). check() allocates nothing.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "tmpc/io/protocol.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/model/state_layout.hpp"

namespace tmpc {

struct StateGateSettings {
  double period = 0.0;          ///< T_f, s: time between frames for one sequence number
  double time_tolerance = 0.5;  ///< fraction of T_f
  int horizon = 50;             ///< periods of prediction
  int resync_frames = 3;
  Eigen::VectorXd jump;         ///< per measured state, physical units, > 0
  void validate() const;        ///< throws std::invalid_argument naming the field
};

/// The gate's settings from the config's `link` section: thresholds per group, a
/// group without one set gets half of its widest half-width in `half_widths` (the
/// error box, physical); `kinds` and `half_widths` cover the measured states.
StateGateSettings state_gate_settings(const LinkSettings& l, const std::vector<StateKind>& kinds,
                                      const Eigen::VectorXd& half_widths, double period);

/// Absolute bounds of the measured state for the decoder (io), per kind.
io::DecoderSettings state_decoder_settings(const LinkSettings& l, const std::vector<StateKind>& kinds);

class StateGate {
 public:
  enum class Verdict { Accepted, First, Resynced, RejectedTime, RejectedJump };
  /// A (p x p) and B (p x m): the normalized nominal model of the p measured states;
  /// N_x (p), N_u (m): their normalizations (x_n = N_x x); kinds: p entries.
  StateGate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::VectorXd& N_x,
            const Eigen::VectorXd& N_u, std::vector<StateKind> kinds, StateGateSettings s);
  /// A frame at time t with sequence number seq and measured error e (p entries,
  /// physical); u_tilde = u - u_r (m entries, physical) applied since the last frame.
  Verdict check(double t, std::uint32_t seq, const Eigen::VectorXd& e, const Eigen::VectorXd& u_tilde);
  /// The next frame starts a new track (a new session, a re-anchored sequence).
  void reset();
  static bool accepted(Verdict v) { return v == Verdict::Accepted || v == Verdict::First || v == Verdict::Resynced; }
  /// Time and jump rejections, resyncs (the decoder counts the rest).
  const io::LinkCounts& counts() const { return counts_; }

 private:
  struct Track {
    bool valid = false;
    double t = 0.0;
    std::uint32_t seq = 0;
    Eigen::VectorXd e_n;  ///< normalized
  };
  /// Both tests of a frame against a track; the verdict names the failing one.
  Verdict test(const Track& from, double t, std::uint32_t seq, const Eigen::VectorXd& e_n);
  void adopt(Track& tr, double t, std::uint32_t seq, const Eigen::VectorXd& e_n);
  Eigen::MatrixXd A_, B_;
  Eigen::VectorXd N_x_, N_u_;
  std::vector<StateKind> kinds_;
  StateGateSettings s_;
  Track last_, run_;
  int run_length_ = 0;
  Eigen::VectorXd e_n_, u_n_, pred_, tmp_, Bu_;
  io::LinkCounts counts_;
};

}  // namespace tmpc
