// Reference trajectories (see trajectory.hpp).
#include "tmpc/model/trajectory.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "tmpc/model/quintic_spline.hpp"

namespace tmpc {

namespace {

std::string num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

class Helix final : public Trajectory {
 public:
  explicit Helix(const HelixShape& s) : s_(s) {}
  TrajectoryPoint at(double t) const override {
    const double w = s_.angular_rate, c = std::cos(w * t), sn = std::sin(w * t), r = s_.radius, a = s_.z_amplitude;
    TrajectoryPoint p;
    p.p = s_.center + Eigen::Vector3d(r * c, r * sn, -a * c);
    p.v << -r * w * sn, r * w * c, a * w * sn;
    p.a << -r * w * w * c, -r * w * w * sn, a * w * w * c;
    p.psi = s_.yaw;
    return p;
  }
  std::string description() const override {
    return "helix r = " + num(s_.radius) + " m, z " + num(s_.center.z()) + " -+ " + num(s_.z_amplitude) + " m, " +
           num(s_.angular_rate) + " rad/s";
  }

 private:
  HelixShape s_;
};

class Hover final : public Trajectory {
 public:
  explicit Hover(const HoverShape& s) : s_(s) {}
  TrajectoryPoint at(double) const override {
    TrajectoryPoint p;
    p.p = s_.position;
    p.psi = s_.yaw;
    return p;
  }
  std::string description() const override {
    return "hover at (" + num(s_.position.x()) + ", " + num(s_.position.y()) + ", " + num(s_.position.z()) + ") m";
  }

 private:
  HoverShape s_;
};

class Circle final : public Trajectory {
 public:
  explicit Circle(const CircleShape& s) : s_(s) {}
  TrajectoryPoint at(double t) const override {
    const double w = s_.angular_rate, c = std::cos(w * t), sn = std::sin(w * t), r = s_.radius;
    TrajectoryPoint p;
    p.p = s_.center + Eigen::Vector3d(r * c, r * sn, 0.0);
    p.v << -r * w * sn, r * w * c, 0.0;
    p.a << -r * w * w * c, -r * w * w * sn, 0.0;
    p.psi = s_.yaw;
    return p;
  }
  std::string description() const override {
    return "circle r = " + num(s_.radius) + " m at z = " + num(s_.center.z()) + " m, " + num(s_.angular_rate) + " rad/s";
  }

 private:
  CircleShape s_;
};

class FigureEight final : public Trajectory {
 public:
  explicit FigureEight(const FigureEightShape& s) : s_(s) {}
  TrajectoryPoint at(double t) const override {
    const double w = s_.angular_rate, ax = s_.amplitude.x(), ay = s_.amplitude.y();
    const double s1 = std::sin(w * t), c1 = std::cos(w * t), s2 = std::sin(2 * w * t), c2 = std::cos(2 * w * t);
    TrajectoryPoint p;
    p.p = s_.center + Eigen::Vector3d(ax * s1, 0.5 * ay * s2, 0.0);
    p.v << ax * w * c1, ay * w * c2, 0.0;
    p.a << -ax * w * w * s1, -2.0 * ay * w * w * s2, 0.0;
    p.psi = s_.yaw;
    return p;
  }
  std::string description() const override {
    return "figure-eight " + num(2 * s_.amplitude.x()) + " x " + num(s_.amplitude.y()) + " m at z = " +
           num(s_.center.z()) + " m, " + num(s_.angular_rate) + " rad/s";
  }

 private:
  FigureEightShape s_;
};

/// Three coordinates (and optionally the yaw) as C4 quintic splines of time.
class SplinePath final : public Trajectory {
 public:
  SplinePath(std::vector<QuinticSpline> xyz, QuinticSpline yaw, double constant_yaw, bool spline_yaw, std::string what,
             bool rests_at_end)
      : xyz_(std::move(xyz)), yaw_(std::move(yaw)), constant_yaw_(constant_yaw), spline_yaw_(spline_yaw),
        what_(std::move(what)), rests_at_end_(rests_at_end) {}
  TrajectoryPoint at(double t) const override {
    TrajectoryPoint p;
    double jerk;
    for (int i = 0; i < 3; ++i) xyz_[static_cast<std::size_t>(i)].evaluate(t, p.p(i), p.v(i), p.a(i), jerk);
    if (spline_yaw_) {
      yaw_.evaluate(t, p.psi, p.psi_d, p.psi_dd, jerk);
    } else {
      p.psi = constant_yaw_;
    }
    return p;
  }
  /// A path that ends at rest holds its last point for ever; one that does not ends.
  double duration() const override { return rests_at_end_ ? std::numeric_limits<double>::infinity() : xyz_[0].end(); }
  std::string description() const override { return what_; }

 private:
  std::vector<QuinticSpline> xyz_;
  QuinticSpline yaw_;
  double constant_yaw_;
  bool spline_yaw_;
  std::string what_;
  bool rests_at_end_;
};

/// Peak |v| and |a| of a spline path, sampled densely on every segment.
void peaks(const SplinePath& s, const std::vector<double>& knots, double& v_peak, double& a_peak) {
  v_peak = a_peak = 0.0;
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    for (int j = 0; j <= 64; ++j) {
      const TrajectoryPoint p = s.at(knots[k] + (knots[k + 1] - knots[k]) * j / 64.0);
      v_peak = std::max(v_peak, p.v.norm());
      a_peak = std::max(a_peak, p.a.norm());
    }
  }
}

std::vector<QuinticSpline> splines_at(const std::vector<double>& t, const std::vector<Eigen::Vector3d>& pts) {
  std::vector<QuinticSpline> out;
  for (int i = 0; i < 3; ++i) {
    std::vector<double> y;
    for (const Eigen::Vector3d& q : pts) y.push_back(q(i));
    out.emplace_back(t, y, QuinticSpline::Ends::Clamped);  // at rest at both ends
  }
  return out;
}

}  // namespace

std::unique_ptr<Trajectory> make_helix(const HelixShape& s) { return std::make_unique<Helix>(s); }
std::unique_ptr<Trajectory> make_hover(const HoverShape& s) { return std::make_unique<Hover>(s); }
std::unique_ptr<Trajectory> make_circle(const CircleShape& s) { return std::make_unique<Circle>(s); }
std::unique_ptr<Trajectory> make_figure_eight(const FigureEightShape& s) { return std::make_unique<FigureEight>(s); }

std::vector<double> waypoint_schedule(const WaypointPath& w) {
  if (w.points.size() < 2) throw std::invalid_argument("waypoints: need at least 2 points, got " + std::to_string(w.points.size()));
  if (!(w.max_speed > 0.0) || !(w.max_acceleration > 0.0)) {
    throw std::invalid_argument("waypoints: max_speed and max_acceleration must be positive");
  }
  // First segment times from the distances at the limits (a rest-to-rest profile
  // would need 2 sqrt(d / a) and d / v), then one exact rescaling: the minimum-jerk
  // spline through the same points with all times scaled by s is p(t / s), so its
  // speed scales by 1 / s and its acceleration by 1 / s^2.
  std::vector<double> t = {0.0};
  for (std::size_t k = 1; k < w.points.size(); ++k) {
    const double d = (w.points[k] - w.points[k - 1]).norm();
    if (!(d > 1e-9)) throw std::invalid_argument("waypoints: point " + std::to_string(k) + " repeats point " + std::to_string(k - 1));
    t.push_back(t.back() + std::max({d / w.max_speed, 2.0 * std::sqrt(d / w.max_acceleration), 0.1}));
  }
  double v_peak = 0.0, a_peak = 0.0;
  {
    const SplinePath first(splines_at(t, w.points), QuinticSpline(), w.yaw, false, "", true);
    peaks(first, t, v_peak, a_peak);
  }
  const double s = std::max(v_peak / w.max_speed, std::sqrt(a_peak / w.max_acceleration)) * 1.001;
  for (double& tk : t) tk *= s;
  return t;
}

std::unique_ptr<Trajectory> make_waypoints(const WaypointPath& w) {
  const std::vector<double> t = waypoint_schedule(w);
  std::ostringstream os;
  os << "waypoints (" << w.points.size() << " points, " << t.back() << " s, |v| <= " << w.max_speed
     << " m/s, |a| <= " << w.max_acceleration << " m/s^2)";
  return std::make_unique<SplinePath>(splines_at(t, w.points), QuinticSpline(), w.yaw, false, os.str(), true);
}

std::unique_ptr<Trajectory> make_csv_trajectory(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) -> void {
    throw std::invalid_argument(source + ": line " + std::to_string(line_no) + ": " + what);
  };
  // Header: t, x, y, z, psi.
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line[0] != '#') break;
  }
  {
    std::string h;
    for (char c : line) {
      if (c != ' ' && c != '\r') h += c;
    }
    if (h != "t,x,y,z,psi") fail("expected the header 't,x,y,z,psi', got '" + line + "'");
  }
  std::vector<double> t, x, y, z, psi;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    std::istringstream row(line);
    std::string cell;
    double v[5];
    int k = 0;
    while (std::getline(row, cell, ',')) {
      if (k >= 5) fail("more than 5 columns");
      char* end = nullptr;
      v[k] = std::strtod(cell.c_str(), &end);
      while (end != nullptr && (*end == ' ' || *end == '\r')) ++end;
      if (end == cell.c_str() || (end != nullptr && *end != '\0')) fail("'" + cell + "' in column " + std::to_string(k + 1) + " is not a number");
      if (!std::isfinite(v[k])) fail("column " + std::to_string(k + 1) + " is not finite (" + cell + ")");
      ++k;
    }
    if (k != 5) fail("expected 5 columns (t, x, y, z, psi), got " + std::to_string(k));
    if (!t.empty() && !(v[0] > t.back())) fail("time " + num(v[0]) + " is not after " + num(t.back()) + " (rows must be sorted by time)");
    t.push_back(v[0]);
    x.push_back(v[1]);
    y.push_back(v[2]);
    z.push_back(v[3]);
    // Unwrap the yaw so that its spline does not see 2 pi jumps.
    psi.push_back(psi.empty() ? v[4] : psi.back() + std::remainder(v[4] - psi.back(), 2.0 * M_PI));
  }
  if (t.size() < 4) {
    throw std::invalid_argument(source + ": " + std::to_string(t.size()) + " rows of data: a trajectory needs at least 4");
  }
  std::vector<QuinticSpline> xyz;
  for (const std::vector<double>* c : {&x, &y, &z}) xyz.emplace_back(t, *c, QuinticSpline::Ends::Natural);
  QuinticSpline yaw(t, psi, QuinticSpline::Ends::Natural);
  std::ostringstream os;
  os << "csv " << source << " (" << t.size() << " rows, " << t.front() << " to " << t.back() << " s)";
  if (t.front() != 0.0) {
    throw std::invalid_argument(source + ": the first row's time is " + num(t.front()) + " s: a mission starts at t = 0");
  }
  return std::make_unique<SplinePath>(std::move(xyz), std::move(yaw), 0.0, true, os.str(), false);
}

std::unique_ptr<Trajectory> load_csv_trajectory(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::invalid_argument(path + ": cannot open the trajectory: " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw std::invalid_argument(path + ": not a regular file");
  if (st.st_size > (64L << 20)) throw std::invalid_argument(path + ": larger than 64 MiB");
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return make_csv_trajectory(ss.str(), path);
}

}  // namespace tmpc
