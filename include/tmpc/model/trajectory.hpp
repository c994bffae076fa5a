// Reference trajectories of the load: position and yaw with their derivatives up to
// what the feedforward (5.4) needs (velocity, acceleration; the trim makes the
// attitude quasi-static, reference.hpp). Shapes:
//   helix (thesis 6.2)  x = cx + r cos(w t), y = cy + r sin(w t), z = z0 - a cos(w t)
//   hover               a fixed point
//   circle              x = cx + r cos(w t), y = cy + r sin(w t), z = cz
//   figure-eight        x = cx + ax sin(w t), y = cy + (ay / 2) sin(2 w t), z = cz (Gerono)
//   waypoints           a minimum-jerk C4 quintic spline through the points, at rest at
//                       both ends, its times scaled so that |v| <= v_max, |a| <= a_max
//   csv                 rows t, x, y, z, psi; derivatives from a C4 quintic spline
//                       through the samples (natural ends)
// The yaw is constant for the shapes and the waypoints, a spline of the (unwrapped)
// samples for a CSV. Past its end a finite trajectory holds its last point at rest.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace tmpc {

struct TrajectoryPoint {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  ///< load position, m
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  ///< m/s
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< m/s^2 (the LPV parameter sigma)
  double psi = 0.0, psi_d = 0.0, psi_dd = 0.0;  ///< yaw, rad, rad/s, rad/s^2
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual TrajectoryPoint at(double t) const = 0;
  /// Seconds it is defined for: infinity for the periodic shapes and hover.
  virtual double duration() const { return std::numeric_limits<double>::infinity(); }
  /// "helix r = 5 m, ..." for reports.
  virtual std::string description() const = 0;
};

struct HelixShape {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< cx, cy, z0
  double radius = 0.0, z_amplitude = 0.0, angular_rate = 0.0, yaw = 0.0;
};
struct HoverShape {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};
struct CircleShape {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0.0, angular_rate = 0.0, yaw = 0.0;
};
struct FigureEightShape {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector2d amplitude = Eigen::Vector2d::Zero();  ///< ax, ay (the eight is ay / 2 wide in y)
  double angular_rate = 0.0, yaw = 0.0;
};
struct WaypointPath {
  std::vector<Eigen::Vector3d> points;  ///< at least 2
  double max_speed = 0.0, max_acceleration = 0.0, yaw = 0.0;
};

std::unique_ptr<Trajectory> make_helix(const HelixShape& s);
std::unique_ptr<Trajectory> make_hover(const HoverShape& s);
std::unique_ptr<Trajectory> make_circle(const CircleShape& s);
std::unique_ptr<Trajectory> make_figure_eight(const FigureEightShape& s);
/// Throws std::invalid_argument for fewer than 2 points, repeated consecutive points
/// or non-positive limits.
std::unique_ptr<Trajectory> make_waypoints(const WaypointPath& w);
/// The times at which that path passes its points (0 first).
std::vector<double> waypoint_schedule(const WaypointPath& w);
/// CSV text with a header line naming t, x, y, z, psi (in that order) and at least 4
/// rows, time strictly increasing, every value finite; `source` names the file in
/// errors, which give the line ("track.csv: line 7: time 1.2 is not after 1.3").
/// Throws std::invalid_argument.
std::unique_ptr<Trajectory> make_csv_trajectory(const std::string& csv_text, const std::string& source);
/// The same from a file (a regular file of at most 64 MiB).
std::unique_ptr<Trajectory> load_csv_trajectory(const std::string& path);

}  // namespace tmpc
