// Rod statics against the state box (see force_envelope.hpp).
#include "tmpc/runtime/force_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "tmpc/model/reference.hpp"
#include "tmpc/sets/lp.hpp"

namespace tmpc {

namespace {

/// Angle range [lo, hi] per axis over the whole flight: reference -+ bound.
struct AngleRanges {
  double lo[3], hi[3];
};

/// Slope (r_x, r_y) / r_z of r = Rz(psi) Ry(theta) Rx(phi) e_z.
Eigen::Vector2d rod_slope(double phi, double theta, double psi) {
  const double cf = std::cos(phi), sf = std::sin(phi), ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(psi), sp = std::sin(psi);
  const Eigen::Vector3d r(cf * st * cp + sf * sp, cf * st * sp - sf * cp, cf * ct);
  return r.head<2>() / r.z();
}

/// An outer polygon of conv S: its support in K directions, n_k' s <= c_k with c_k the
/// largest n_k' s over S sampled (the boundary curves every 1/200 of the phi and theta
/// ranges, every 1/100 of psi's) plus `kMargin`, more than the samples' sag (~1e-5).
/// Between two directions the polygon exceeds conv S by at most its radius times
/// (1 / cos(pi / K) - 1), 2.4e-5 of a slope here: a little weaker, never unsound.
struct SlopeHull {
  std::vector<Eigen::Vector2d> normal;
  std::vector<double> offset;
  bool contains(const Eigen::Vector2d& s) const {
    for (std::size_t k = 0; k < normal.size(); ++k)
      if (normal[k].dot(s) > offset[k]) return false;
    return true;
  }
};

SlopeHull admissible_slopes(const AngleRanges& r) {
  constexpr int kEdge = 200, kYaw = 100, kDirections = 512;
  constexpr double kMargin = 1e-4;
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(static_cast<std::size_t>((4 * kEdge + 1) * (kYaw + 1)));
  for (int j = 0; j <= kYaw; ++j) {
    const double psi = r.lo[2] + (r.hi[2] - r.lo[2]) * j / kYaw;
    for (int i = 0; i < kEdge; ++i) {
      const double f = r.lo[0] + (r.hi[0] - r.lo[0]) * i / kEdge;
      const double th = r.lo[1] + (r.hi[1] - r.lo[1]) * i / kEdge;
      pts.push_back(rod_slope(f, r.lo[1], psi));
      pts.push_back(rod_slope(f, r.hi[1], psi));
      pts.push_back(rod_slope(r.lo[0], th, psi));
      pts.push_back(rod_slope(r.hi[0], th, psi));
    }
    pts.push_back(rod_slope(r.hi[0], r.hi[1], psi));
  }
  SlopeHull s;
  for (int k = 0; k < kDirections; ++k) {
    const double angle = 2.0 * M_PI * k / kDirections;
    const Eigen::Vector2d n(std::cos(angle), std::sin(angle));
    double c = -1e300;
    for (const Eigen::Vector2d& p : pts) c = std::max(c, n.dot(p));
    s.normal.push_back(n);
    s.offset.push_back(c + kMargin);
  }
  return s;
}

int index_of(const ControllerArtifact& a, const char* name) {
  const auto it = std::find(a.state_names.begin(), a.state_names.end(), name);
  return it == a.state_names.end() ? -1 : static_cast<int>(it - a.state_names.begin());
}

/// Whether some mean acceleration in [lo, hi] puts m_L a + G in the cone over the hull:
/// n_k' (m_L a_xy + G_xy) <= c_k (m_L a_z + G_z) for every k (the rod in tension,
/// m_L a_z + G_z > 0 over the box: checked by the caller).
bool admissible_mean(const SlopeHull& hull, double m_load, const Eigen::Vector3d& G, const Eigen::Vector3d& lo,
                     const Eigen::Vector3d& hi) {
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  const Eigen::Vector3d v = m_load * mid + G;
  if (hull.contains(v.head<2>() / v.z())) return true;  // the middle acceleration already fits
  const int rows = static_cast<int>(hull.normal.size());
  Eigen::MatrixXd A(rows, 3);
  Eigen::VectorXd b(rows);
  for (int k = 0; k < rows; ++k) {
    const Eigen::Vector2d& n = hull.normal[static_cast<std::size_t>(k)];
    const double c = hull.offset[static_cast<std::size_t>(k)];
    A.row(k) << m_load * n.x(), m_load * n.y(), -m_load * c;
    b(k) = c * G.z() - n.dot(G.head<2>());
  }
  const LpResult r = solve_lp(Eigen::VectorXd::Zero(3), A, b, Eigen::MatrixXd(0, 3), Eigen::VectorXd(0), lo, hi);
  return r.status != LpStatus::Infeasible;
}

}  // namespace

ForceEnvelopeReport check_force_envelope(const ControllerArtifact& a, const Trajectory& t,
                                         const DisturbanceProfile& d, double duration,
                                         const VehicleParams* plant) {
  ForceEnvelopeReport rep;
  const int i_phi = index_of(a, "phi"), i_theta = index_of(a, "theta"), i_psi = index_of(a, "psi");
  const int i_v[3] = {index_of(a, "d_x"), index_of(a, "d_y"), index_of(a, "d_z")};
  if (a.model != ModelKind::Tiltrotor || i_phi < 0 || i_theta < 0 || i_psi < 0 || i_v[0] < 0 || i_v[1] < 0 ||
      i_v[2] < 0) {
    rep.message = "no load on a rod in this model";
    return rep;
  }
  const double T = a.sample_time;
  const long periods = std::lround(duration / T);
  std::vector<Eigen::Vector3d> force(static_cast<std::size_t>(periods + 1));
  bool any = false;
  for (long k = 0; k <= periods; ++k) {
    force[static_cast<std::size_t>(k)] = d.load_force(static_cast<double>(k) * T);
    any = any || force[static_cast<std::size_t>(k)].norm() > 0.0;
  }
  if (!any) {
    rep.message = "no force on the load";
    return rep;
  }
  rep.applicable = true;
  auto half_width = [&](int i) { return a.X.hi(i) / a.N_x(i); };
  const double bound[3] = {half_width(i_phi), half_width(i_theta), half_width(i_psi)};
  const Eigen::Vector3d dv_max(half_width(i_v[0]), half_width(i_v[1]), half_width(i_v[2]));
  const VehicleParams& vp = plant ? *plant : a.vehicle;
  const double m_load = vp.load_mass, g = vp.gravity;

  // The reference along the flight: the load's velocity every period, its trimmed
  // attitude every 10th (the trim dominates the cost; the attitude moves slowly, and the
  // ranges are widened by the largest change between two trims).
  const TiltrotorModel model(a.vehicle);
  ReferenceGenerator gen(model, std::shared_ptr<const Trajectory>(&t, [](const Trajectory*) {}), a.attitude);
  std::vector<Eigen::Vector3d> eta(force.size()), vel(force.size());
  AngleRanges range{{1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}};
  Eigen::Vector3d step = Eigen::Vector3d::Zero();
  for (long k = 0; k <= periods; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const double tt = static_cast<double>(k) * T;
    vel[kk] = t.at(tt).v;
    if (k % 10 != 0 && k != periods) {
      eta[kk] = eta[kk - 1];
      continue;
    }
    eta[kk] = gen.at(tt).q.segment<3>(3);
    if (k > 0) step = step.cwiseMax((eta[kk] - eta[static_cast<std::size_t>((k - 1) / 10 * 10)]).cwiseAbs());
    for (int i = 0; i < 3; ++i) {
      range.lo[i] = std::min(range.lo[i], eta[kk](i) - bound[i]);
      range.hi[i] = std::max(range.hi[i], eta[kk](i) + bound[i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    range.lo[i] -= step(i);
    range.hi[i] += step(i);
  }

  // Static tilt: the rod along -F + m_L g e_z, seen in the reference's yaw, and in the
  // best yaw within psi's bound of it.
  static const char* const angle_name[2] = {"phi", "theta"};
  constexpr int kYaws = 2000;
  for (long k = 0; k <= periods; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const Eigen::Vector3d world = m_load * g * Eigen::Vector3d::UnitZ() - force[kk];
    if (!(world.z() > 0.0)) continue;  // the rod in compression: beyond this check
    auto ratios = [&](double psi, double* ratio) {
      const Eigen::Vector3d n = Eigen::AngleAxisd(-psi, Eigen::Vector3d::UnitZ()) * world;
      const double phi = -std::asin(n.y() / n.norm()), theta = std::atan2(n.x(), n.z());
      ratio[0] = std::abs(phi - eta[kk](0)) / bound[0];
      ratio[1] = std::abs(theta - eta[kk](1)) / bound[1];
    };
    double ratio[2];
    ratios(eta[kk](2), ratio);
    for (int i = 0; i < 2; ++i) {
      if (ratio[i] > rep.static_peak) {
        rep.static_peak = ratio[i];
        rep.static_peak_time = static_cast<double>(k) * T;
        rep.static_peak_state = angle_name[i];
      }
    }
    const bool outside = std::max(ratio[0], ratio[1]) > 1.0;
    if (outside) rep.static_outside += T;
    double best = std::max(ratio[0], ratio[1]);
    if (best <= std::min(1.0, rep.static_peak_best_yaw)) continue;  // the yaw cannot raise either figure
    int inside = 0;  // yaws of the grid that bring an outside tilt inside
    double first = 0.0, last = 0.0;
    for (int j = 0; j <= kYaws; ++j) {
      const double turn = bound[2] * (2.0 * j / kYaws - 1.0);
      ratios(eta[kk](2) + turn, ratio);
      const double larger = std::max(ratio[0], ratio[1]);
      best = std::min(best, larger);
      if (outside && larger <= 1.0) {
        if (inside++ == 0) first = turn;
        last = turn;
      }
    }
    const double window = inside * 2.0 * bound[2] / kYaws;
    if (outside && window < rep.yaw_window_min) {
      rep.yaw_window_min = window;
      rep.yaw_window_time = static_cast<double>(k) * T;
      rep.yaw_window_first = first;
      rep.yaw_window_last = last;
    }
    if (best > rep.static_peak_best_yaw) {
      rep.static_peak_best_yaw = best;
      rep.static_peak_best_yaw_time = static_cast<double>(k) * T;
    }
    if (best > 1.0) rep.static_outside_best_yaw += T;
  }

  // Certified windows: every 10th period, each length; then the earliest-ending disjoint ones.
  std::vector<Eigen::Vector3d> prefix(force.size() + 1, Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < force.size(); ++k) prefix[k + 1] = prefix[k] + force[k];
  auto certify = [&](const AngleRanges& angles) {
    const SlopeHull hull = admissible_slopes(angles);
    std::vector<ForceWindow> found, disjoint;
    for (const double w : force_window_lengths()) {
      const long len = std::lround(w / T);
      for (long k0 = 0; k0 + len <= periods; k0 += 10) {
        const auto s = static_cast<std::size_t>(k0), e = static_cast<std::size_t>(k0 + len);
        const Eigen::Vector3d f_mean = (prefix[e + 1] - prefix[s]) / static_cast<double>(len + 1);
        const double span = static_cast<double>(len) * T;
        const Eigen::Vector3d dv_r = vel[e] - vel[s];
        const Eigen::Vector3d lo = (dv_r - 2.0 * dv_max) / span, hi = (dv_r + 2.0 * dv_max) / span;
        const Eigen::Vector3d G = m_load * g * Eigen::Vector3d::UnitZ() - f_mean;
        if (!(m_load * lo.z() + G.z() > 0.0)) continue;  // the rod might be in compression: no conclusion
        if (!admissible_mean(hull, m_load, G, lo, hi))
          found.push_back({static_cast<double>(k0) * T, static_cast<double>(k0 + len) * T});
      }
    }
    std::sort(found.begin(), found.end(), [](const ForceWindow& x, const ForceWindow& y) { return x.end < y.end; });
    for (const ForceWindow& f : found)
      if (disjoint.empty() || f.start > disjoint.back().end) disjoint.push_back(f);
    return disjoint;
  };
  rep.certified = certify(range);
  AngleRanges held = range;  // the yaw held on its reference
  held.lo[2] += bound[2];
  held.hi[2] -= bound[2];
  rep.certified_reference_yaw = certify(held);

  std::ostringstream os;
  os << "forces on the load: static tilt up to " << rep.static_peak << " of the " << rep.static_peak_state
     << " bound (t = " << rep.static_peak_time << " s), outside the box for " << rep.static_outside
     << " s; at the best yaw within psi's bound up to " << rep.static_peak_best_yaw << " (t = "
     << rep.static_peak_best_yaw_time << " s), outside for " << rep.static_outside_best_yaw << " s; ";
  if (std::isfinite(rep.yaw_window_min)) {
    os << "the yaws that bring it inside span at least " << rep.yaw_window_min << " rad (t = " << rep.yaw_window_time
       << " s: from " << rep.yaw_window_first << " to " << rep.yaw_window_last << " rad off the reference); ";
  }
  auto windows = [&](const std::vector<ForceWindow>& w) {
    os << w.size() << " disjoint window(s)";
    if (!w.empty()) os << " (first " << w[0].start << " to " << w[0].end << " s)";
  };
  os << "certified outside the box: ";
  windows(rep.certified);
  os << " for every controller, ";
  windows(rep.certified_reference_yaw);
  os << " for one that holds the reference yaw";
  if (!rep.certified.empty()) os << ": no controller flies this without violations";
  rep.message = os.str();
  return rep;
}

}  // namespace tmpc
