// Plausibility gate of the measured state (see state_gate.hpp).
#include "tmpc/runtime/state_gate.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tmpc {

void StateGateSettings::validate() const {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("state gate: " + what);
  };
  need(period > 0.0 && std::isfinite(period), "period must be positive");
  need(time_tolerance > 0.0, "time_tolerance must be positive");
  need(horizon >= 1, "horizon must be >= 1");
  need(resync_frames >= 2, "resync_frames must be >= 2");
  need(jump.size() > 0 && jump.allFinite() && (jump.array() > 0.0).all(), "every jump threshold must be positive");
}

StateGateSettings state_gate_settings(const LinkSettings& l, const std::vector<StateKind>& kinds,
                                      const Eigen::VectorXd& half_widths, double period) {
  if (static_cast<Eigen::Index>(kinds.size()) != half_widths.size()) {
    throw std::invalid_argument("state gate: " + std::to_string(kinds.size()) + " kinds for " +
                                std::to_string(half_widths.size()) + " half-widths");
  }
  const double configured[4] = {l.jump_position, l.jump_angle, l.jump_velocity, l.jump_rate};
  double widest[4] = {0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const StateGroup g = group_of(kinds[i]);
    if (g != StateGroup::None) widest[static_cast<int>(g)] = std::max(widest[static_cast<int>(g)], half_widths(static_cast<Eigen::Index>(i)));
  }
  StateGateSettings s;
  s.period = period;
  s.time_tolerance = l.time_tolerance;
  s.horizon = l.gate_horizon;
  s.resync_frames = l.resync_frames;
  s.jump.resize(half_widths.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const StateGroup g = group_of(kinds[i]);
    const int gi = static_cast<int>(g);
    s.jump(static_cast<Eigen::Index>(i)) =
        g == StateGroup::None ? 1e300 : (configured[gi] > 0.0 ? configured[gi] : 0.5 * widest[gi]);
  }
  s.validate();
  return s;
}

io::DecoderSettings state_decoder_settings(const LinkSettings& l, const std::vector<StateKind>& kinds) {
  io::DecoderSettings d = io::state_decoder_settings(kinds.size());
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    double b = 0.0;
    switch (kinds[i]) {
      case StateKind::Position: b = l.bound_position; break;
      case StateKind::Angle: b = l.bound_angle; break;
      case StateKind::Yaw: b = l.bound_yaw; break;
      case StateKind::Velocity: b = l.bound_velocity; break;
      case StateKind::AngularRate: b = l.bound_rate; break;
      case StateKind::Integral: b = 1e9; break;
    }
    d.bound[i] = b;
  }
  d.time_bound = l.bound_time;
  d.sequence_window = static_cast<std::uint32_t>(l.sequence_window);
  d.resync_frames = l.resync_frames;
  d.session_confirm = l.session_confirm;
  d.validate();
  return d;
}

StateGate::StateGate(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::VectorXd& N_x,
                     const Eigen::VectorXd& N_u, std::vector<StateKind> kinds, StateGateSettings s)
    : A_(A), B_(B), N_x_(N_x), N_u_(N_u), kinds_(std::move(kinds)), s_(std::move(s)) {
  s_.validate();
  const Eigen::Index p = A.rows();
  if (A.cols() != p || B.rows() != p || N_x.size() != p || B.cols() != N_u.size() ||
      static_cast<Eigen::Index>(kinds_.size()) != p || s_.jump.size() != p) {
    throw std::invalid_argument("state gate: A " + std::to_string(A.rows()) + "x" + std::to_string(A.cols()) + ", B " +
                                std::to_string(B.rows()) + "x" + std::to_string(B.cols()) + ", N_x " +
                                std::to_string(N_x.size()) + ", N_u " + std::to_string(N_u.size()) + ", " +
                                std::to_string(kinds_.size()) + " kinds and " + std::to_string(s_.jump.size()) +
                                " thresholds disagree");
  }
  last_.e_n = run_.e_n = e_n_ = pred_ = tmp_ = Bu_ = Eigen::VectorXd::Zero(p);
  u_n_ = Eigen::VectorXd::Zero(B.cols());
}

void StateGate::reset() {
  last_.valid = run_.valid = false;
  run_length_ = 0;
}

void StateGate::adopt(Track& tr, double t, std::uint32_t seq, const Eigen::VectorXd& e_n) {
  tr.valid = true;
  tr.t = t;
  tr.seq = seq;
  tr.e_n = e_n;
}

StateGate::Verdict StateGate::test(const Track& from, double t, std::uint32_t seq, const Eigen::VectorXd& e_n) {
  const double dt = t - from.t;
  const long k = static_cast<long>(static_cast<std::int32_t>(seq - from.seq));
  if (!(dt > 0.0) || k < 1 || std::abs(dt - static_cast<double>(k) * s_.period) > s_.time_tolerance * s_.period) {
    return Verdict::RejectedTime;
  }
  const long n = std::lround(dt / s_.period);
  if (n < 1 || n > s_.horizon) return Verdict::Accepted;  // no prediction that far
  // e_pred = A^n e_last + sum_{i<n} A^i B u~, by n steps of x+ = A x + B u~.
  Bu_.noalias() = B_ * u_n_;
  pred_ = from.e_n;
  for (long i = 0; i < n; ++i) {
    tmp_.noalias() = A_ * pred_;
    pred_ = tmp_ + Bu_;
  }
  // The thresholds are for one period; what the model misses grows with the
  // prediction: 10 % more per further period.
  const double grow = 1.0 + 0.1 * static_cast<double>(n - 1);
  for (Eigen::Index i = 0; i < pred_.size(); ++i) {
    double d = (e_n(i) - pred_(i)) / N_x_(i);  // physical
    if (kinds_[static_cast<std::size_t>(i)] == StateKind::Yaw) d = std::remainder(d, 2.0 * M_PI);
    if (std::abs(d) > s_.jump(i) * grow) return Verdict::RejectedJump;
  }
  return Verdict::Accepted;
}

StateGate::Verdict StateGate::check(double t, std::uint32_t seq, const Eigen::VectorXd& e,
                                    const Eigen::VectorXd& u_tilde) {
  e_n_ = e.cwiseProduct(N_x_);
  u_n_ = u_tilde.cwiseProduct(N_u_);
  if (!last_.valid) {
    adopt(last_, t, seq, e_n_);
    run_.valid = false;
    run_length_ = 0;
    ++counts_.accepted;
    return Verdict::First;
  }
  const Verdict v = test(last_, t, seq, e_n_);
  if (v == Verdict::Accepted) {
    adopt(last_, t, seq, e_n_);
    run_.valid = false;
    run_length_ = 0;
    ++counts_.accepted;
    return v;
  }
  // Rejected: does it continue a run of rejected frames that agree with each other?
  run_length_ = run_.valid && test(run_, t, seq, e_n_) == Verdict::Accepted ? run_length_ + 1 : 1;
  adopt(run_, t, seq, e_n_);
  if (run_length_ >= s_.resync_frames) {
    adopt(last_, t, seq, e_n_);
    run_.valid = false;
    run_length_ = 0;
    ++counts_.resyncs;
    ++counts_.accepted;
    return Verdict::Resynced;
  }
  ++counts_[v == Verdict::RejectedTime ? io::Reject::Time : io::Reject::Jump];
  return v;
}

}  // namespace tmpc
