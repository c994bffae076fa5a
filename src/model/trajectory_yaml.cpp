// Trajectory sections of scenario files (see trajectory_yaml.hpp).
#include "trajectory_yaml.hpp"

#include <stdexcept>

namespace tmpc::detail {

std::string folder_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::unique_ptr<Trajectory> trajectory_from(Section s, const std::string& base_dir) {
  const std::string type = s.text("type", {"helix", "hover", "circle", "figure_eight", "waypoints", "csv"});
  auto yaw = [&] { return s.has("yaw") ? s.number_in("yaw", -M_PI, M_PI) : 0.0; };
  std::unique_ptr<Trajectory> t;
  if (type == "helix") {
    HelixShape h;
    h.center = vec3(s, "center");
    h.radius = s.number_in("radius", 0.0, 1e4);
    h.z_amplitude = s.number_in("z_amplitude", 0.0, 1e4);
    h.angular_rate = s.number_in("angular_rate", 0.0, 100.0);
    h.yaw = yaw();
    t = make_helix(h);
  } else if (type == "hover") {
    HoverShape h;
    h.position = vec3(s, "position");
    h.yaw = yaw();
    t = make_hover(h);
  } else if (type == "circle") {
    CircleShape c;
    c.center = vec3(s, "center");
    c.radius = s.number_in("radius", 0.0, 1e4);
    c.angular_rate = s.number_in("angular_rate", 0.0, 100.0);
    c.yaw = yaw();
    t = make_circle(c);
  } else if (type == "figure_eight") {
    FigureEightShape f;
    f.center = vec3(s, "center");
    const auto a = s.vector("amplitude", 2);
    f.amplitude << a[0], a[1];
    if (a[0] < 0.0 || a[1] < 0.0) s.fail(s.key("amplitude"), "must be >= 0");
    f.angular_rate = s.number_in("angular_rate", 0.0, 100.0);
    f.yaw = yaw();
    t = make_figure_eight(f);
  } else if (type == "waypoints") {
    WaypointPath w;
    YAML::Node pts = s.raw("points");
    if (!pts.IsSequence()) s.fail(s.key("points"), "expected a list of [x, y, z] points");
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const auto v = s.vector_of(pts[i], s.key("points") + "[" + std::to_string(i) + "]", 3);
      w.points.emplace_back(v[0], v[1], v[2]);
    }
    w.max_speed = s.positive("max_speed");
    w.max_acceleration = s.positive("max_acceleration");
    w.yaw = yaw();
    try {
      t = make_waypoints(w);
    } catch (const std::invalid_argument& e) {
      s.fail(s.key("points"), e.what());
    }
  } else {
    const std::string file = s.string("file");
    const std::string path = !file.empty() && file[0] == '/' ? file : base_dir + file;
    try {
      t = load_csv_trajectory(path);
    } catch (const std::invalid_argument& e) {
      s.fail(s.key("file"), e.what());
    }
  }
  s.finish();
  return t;
}

}  // namespace tmpc::detail
