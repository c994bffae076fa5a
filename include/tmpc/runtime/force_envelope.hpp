// Whether any controller can keep a scenario's forces on the load inside the state box
// (`tmpc check`, `tmpc simulate`'s summary). The load hangs from the vehicle on a rigid
// rod fixed to it; its inertia (8e-6 kg m^2) and the joints' friction let the rod carry
// almost no shear, so the rod's force on the load lies along the rod:
//   tau r = m_L a - F + m_L g e_z,   r = Rz(psi) Ry(theta) Rx(phi) e_z      (load's Newton law)
// with a the load's acceleration and F the force on it (thesis 2.2: eta = (phi, theta,
// psi) is the load's attitude, xi its position).
//  - Static tilt: with a = 0 the rod's attitude is fixed by F alone, e.g.
//    phi = atan(F_y / (m_L g - F_z)) at psi = 0: no controller moves it but by the
//    yaw, which turns the split between phi and theta (reported at the reference yaw
//    and at the best yaw within psi's bound).
//  - Certified windows: over [t1, t2] the mean of m_L a is m_L (v(t2) - v(t1)) / T, and
//    the state box bounds the load's velocity error, so the mean acceleration lies in
//    [(dv_r - 2 dv_max) / T, (dv_r + 2 dv_max) / T]. Every r the box admits (phi, theta,
//    psi within their bounds of the reference) has its slope (r_x, r_y) / r_z in a set
//    S, and the window's mean of tau r lies in the cone over conv S. When no admissible
//    mean acceleration puts the mean of m_L a - F + m_L g e_z in that cone (a 3-variable
//    LP), the rod leaves the box at some instant of the window, whatever the controller
//    does: each disjoint certified window holds at least one violation. The same with
//    psi held on its reference: what a controller that does not yaw away can hold.
// Sound up to the rod's shear (the load's inertia and the joint friction) and the
// force's mean taken at the sample instants.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "tmpc/model/trajectory.hpp"
#include "tmpc/sim/disturbance.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct ForceWindow {
  double start = 0.0, end = 0.0;  ///< s
};

struct ForceEnvelopeReport {
  bool applicable = false;        ///< a tiltrotor artifact and a force on the load
  std::string message;            ///< one line for the user (why not, when not applicable)
  double static_peak = 0.0;       ///< largest static |angle error| / bound (phi, theta at the reference yaw)
  double static_peak_time = 0.0;  ///< s
  std::string static_peak_state;  ///< phi or theta
  double static_outside = 0.0;    ///< s of the flight with the static tilt outside the box
  /// The same with the yaw anywhere within its bound of the reference (the vehicle
  /// turned so that the tilt splits best between phi and theta): per period the
  /// smallest larger-of-the-two ratio over the yaw (a grid of 2001 yaws: above the
  /// exact minimum by at most 1e-3), and the time it stays above 1. A controller that
  /// yaws cannot do better statically; below 1 the reference yaw is what costs.
  double static_peak_best_yaw = 0.0;
  double static_peak_best_yaw_time = 0.0;  ///< s
  double static_outside_best_yaw = 0.0;    ///< s
  /// How precisely the yaw must be held where the reference yaw's static tilt is
  /// outside the box: per such period the measure of the yaws within psi's bound that
  /// bring it inside (the grid's count times its step, 5e-4 rad at a 0.5 rad bound);
  /// the smallest over the flight, when, and that window's first and last yaw inside
  /// (from the reference yaw; the window may have a gap). 0 where no yaw brings it
  /// inside; infinite (and not reported) where the reference yaw's tilt never leaves.
  double yaw_window_min = std::numeric_limits<double>::infinity();  ///< rad
  double yaw_window_time = 0.0;                                      ///< s
  double yaw_window_first = 0.0, yaw_window_last = 0.0;              ///< rad
  /// Disjoint windows, each certified to hold an instant with the rod outside the box
  /// for every controller (earliest first; at most one violation apiece is implied).
  std::vector<ForceWindow> certified;
  /// The same for a controller that holds the load's yaw on its reference (psi's bound
  /// unused): a linear MPC about the reference cannot use the yaw, whose effect on the
  /// rod's tilt under a force is of second order.
  std::vector<ForceWindow> certified_reference_yaw;
};

/// Window lengths tried, s (each from every 10th period).
inline const std::vector<double>& force_window_lengths() {
  static const std::vector<double> w{0.5, 1.0, 2.0, 4.0, 8.0};
  return w;
}

/// The box and the reference are the artifact's; the load's mass and gravity the plant's
/// (`plant`, default: the artifact's vehicle).
ForceEnvelopeReport check_force_envelope(const ControllerArtifact& a, const Trajectory& t,
                                         const DisturbanceProfile& d, double duration,
                                         const VehicleParams* plant = nullptr);

}  // namespace tmpc
