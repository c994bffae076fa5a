// Scenario files (see scenario.hpp).
#include "tmpc/sim/scenario.hpp"

#include <cmath>
#include <limits>

#include "../model/trajectory_yaml.hpp"
#include "../model/yaml_section.hpp"

namespace tmpc {

namespace {

using detail::Section;
using detail::vec3;

DisturbanceEvent::Target target_of(Section& s) {
  if (!s.has("on")) return DisturbanceEvent::Target::Load;
  return s.text("on", {"load", "body"}) == "load" ? DisturbanceEvent::Target::Load : DisturbanceEvent::Target::Body;
}

DisturbanceEvent event_from(Section s) {
  DisturbanceEvent e;
  const std::string type = s.text("type", {"step", "ramp", "sine", "gust"});
  e.target = target_of(s);
  auto end_or_inf = [&] { return s.has("end") ? s.number_in("end", 0.0, 1e7) : std::numeric_limits<double>::infinity(); };
  if (type == "step") {
    e.kind = DisturbanceEvent::Kind::Step;
    e.start = s.number_in("time", 0.0, 1e7);
    e.end = end_or_inf();
    e.force = vec3(s, "force");
  } else if (type == "ramp") {
    e.kind = DisturbanceEvent::Kind::Ramp;
    e.start = s.number_in("start", 0.0, 1e7);
    e.end = s.number_in("end", 0.0, 1e7);
    e.force = vec3(s, "force");
  } else if (type == "sine") {
    e.kind = DisturbanceEvent::Kind::Sine;
    e.start = s.has("start") ? s.number_in("start", 0.0, 1e7) : 0.0;
    e.end = end_or_inf();
    e.force = vec3(s, "amplitude");
    e.frequency = s.number_in("frequency", 0.0, 1e3);
    e.phase = s.has("phase") ? s.number("phase") : 0.0;
  } else {
    e.kind = DisturbanceEvent::Kind::Gust;
    e.start = s.has("start") ? s.number_in("start", 0.0, 1e7) : 0.0;
    e.end = end_or_inf();
    e.magnitude = s.number_in("magnitude", 0.0, 1e3);
    e.time_constant = s.positive("time_constant");
    e.redraw = s.positive("redraw");
    e.seed = s.has("seed") ? static_cast<std::uint32_t>(s.integer_in("seed", 0, 2147483647L)) : 1;
    e.horizontal = s.has("horizontal") && s.flag("horizontal");
  }
  if (!(e.end > e.start)) s.fail(s.key("end"), "must come after the start");
  s.finish();
  return e;
}

void noise_from(Section s, NoiseSpec& n) {
  n.seed = s.has("seed") ? static_cast<std::uint32_t>(s.integer_in("seed", 0, 2147483647L)) : 1;
  const char* groups[4] = {"position", "angle", "velocity", "angular_rate"};
  for (int g = 0; g < 4; ++g) {
    if (!s.has(groups[g])) continue;
    Section gs = s.section(groups[g]);
    if (gs.has("white")) n.white[static_cast<std::size_t>(g)] = gs.number_in("white", 0.0, 1e3);
    if (gs.has("bias")) n.bias[static_cast<std::size_t>(g)] = gs.number_in("bias", -1e3, 1e3);
    if (gs.has("outlier")) {
      Section os = gs.section("outlier");  // {size, probability}: a glitch per sample and row
      n.outlier[static_cast<std::size_t>(g)] = os.number_in("size", 0.0, 1e3);
      n.outlier_probability[static_cast<std::size_t>(g)] = os.number_in("probability", 0.0, 1.0);
      os.finish();
    }
    gs.finish();
  }
  s.finish();
}

ActuatorFault fault_from(Section s) {
  ActuatorFault f;
  const std::string type = s.text("type", {"efficiency", "bias", "stuck"});
  f.input = static_cast<int>(s.integer_in("input", 0, 1000));
  f.start = s.has("start") ? s.number_in("start", 0.0, 1e7) : 0.0;
  f.end = s.has("end") ? s.number_in("end", 0.0, 1e7) : std::numeric_limits<double>::infinity();
  if (type == "efficiency") {
    f.kind = ActuatorFault::Kind::Efficiency;
    f.factor = s.number_in("factor", 0.0, 10.0);
  } else if (type == "bias") {
    f.kind = ActuatorFault::Kind::Bias;
    f.value = s.number_in("value", -1e3, 1e3);
  } else {
    f.kind = ActuatorFault::Kind::Stuck;
  }
  if (!(f.end > f.start)) s.fail(s.key("end"), "must come after the start");
  s.finish();
  return f;
}

void plant_from(Section s, PlantSpec& p) {
  if (s.has("model")) p.model = s.text("model", {"el", "mujoco"});
  if (s.has("scale")) {
    Section f = s.section("scale");
    auto factor = [&](const char* k, double& v) {
      if (f.has(k)) v = f.number_in(k, 0.05, 20.0);
    };
    factor("load_mass", p.scale.load_mass);
    factor("load_inertia", p.scale.load_inertia);
    factor("body_mass", p.scale.body_mass);
    factor("body_inertia", p.scale.body_inertia);
    factor("rotor_mass", p.scale.rotor_mass);
    factor("rotor_inertia", p.scale.rotor_inertia);
    f.finish();
  }
  if (s.has("random")) {
    Section r = s.section("random");
    p.random.fraction = r.number_in("fraction", 0.0, 0.9);
    p.random.distribution = r.has("distribution") ? r.text("distribution", {"uniform", "normal"}) : "uniform";
    p.random.seed = r.has("seed") ? static_cast<unsigned>(r.integer_in("seed", 0, 2147483647L)) : 1;
    p.random.runs = r.has("runs") ? r.integer_in("runs", 1, 1000000) : 10;
    r.finish();
  }
  s.finish();
}

std::string base_name(const std::string& path) {
  std::string b = path.substr(path.find_last_of('/') + 1);
  const auto dot = b.rfind('.');
  return dot == std::string::npos ? b : b.substr(0, dot);
}

}  // namespace

VehicleParams Scenario::plant_vehicle(const VehicleParams& p, int run, long seed) const {
  VehicleParams v = apply_mass_scaling(p, plant.scale);
  if (run >= 0) {
    PerturbationSettings r = plant.random;
    if (seed >= 0) r.seed = static_cast<unsigned>(seed);
    v = apply_mass_scaling(v, draw_mass_scaling(r, run));
  }
  return v;
}

Scenario scenario_from_string(const std::string& yaml, const std::string& source, const std::string& base_dir) {
  Scenario sc;
  sc.source = source;
  Section root(detail::load_single_document(yaml, source), "", sc.source);
  sc.name = root.has("name") ? root.string("name") : base_name(source);
  sc.trajectory = detail::trajectory_from(root.section("trajectory"), base_dir);
  sc.duration = root.number_in("duration", 1e-3, 1e7);
  if (sc.duration > sc.trajectory->duration() + 1e-9) {
    root.fail("duration", "is " + Section::fmt(sc.duration) + " s, longer than the trajectory (" +
                              Section::fmt(sc.trajectory->duration()) + " s): " + sc.trajectory->description());
  }
  if (root.has("start_offset")) {
    Section s = root.section("start_offset");
    if (s.has("position")) sc.start_position_offset = vec3(s, "position");
    if (s.has("yaw")) sc.start_yaw_offset = s.number_in("yaw", -M_PI, M_PI);
    s.finish();
  }
  if (root.has("disturbances")) {
    std::vector<DisturbanceEvent> events;
    for (Section e : root.sections("disturbances")) events.push_back(event_from(e));
    try {
      sc.disturbances = DisturbanceProfile(std::move(events));
    } catch (const std::invalid_argument& e) {
      root.fail("disturbances", e.what());
    }
  }
  if (root.has("noise")) noise_from(root.section("noise"), sc.noise);
  if (root.has("faults")) {
    for (Section f : root.sections("faults")) sc.faults.push_back(fault_from(f));
  }
  if (root.has("plant")) plant_from(root.section("plant"), sc.plant);
  root.finish();
  return sc;
}

Scenario load_scenario(const std::string& path) {
  return scenario_from_string(read_config_file(path, "scenario"), path, detail::folder_of(path));
}

}  // namespace tmpc
