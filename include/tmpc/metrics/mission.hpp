// Closed-loop missions on a virtual clock (thesis 6.2): the helix with the
// disturbance schedule, any plant, the tube controller with any solver; and the
// thesis' metrics: RMSE per coordinate, total control variation per input, solve
// time statistics, fallbacks, clipping, tube exits (in total and per disturbance
// step) and state-constraint violations.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

struct MissionOptions {
  std::string solver = "admm";
  std::string plant = "el";
  double duration = 80.0;
  bool disturbance = true;
  int run = -1;                   ///< Monte Carlo run (masses and inertias perturbed), -1: nominal
  long seed = -1;                 ///< perturbation seed, -1: the config's
  bool reinitialize_nominal = false;
  std::string tube_law;           ///< "" (the config's), "mayne" or "offset-free"
  double observer_gain = 0.0;     ///< > 0: overrides the config's
  std::string telemetry_csv;      ///< one row per period when not empty
  std::string explicit_law;       ///< companion file for solver "explicit"
  /// When set, every period's QP parameter (what the solver was given) is appended:
  /// the mission's QPs, for tests and benchmarks.
  std::vector<Eigen::VectorXd>* record_qps = nullptr;
};

struct MissionMetrics {
  std::array<double, 10> rmse{};            ///< per coordinate, q - q_r
  std::array<double, 3> max_abs_error{};    ///< x, y, z
  std::array<double, 4> tcv{};              ///< sum |u_k - u_(k-1)|
  double solve_min = 0, solve_mean = 0, solve_p50 = 0, solve_p99 = 0, solve_max = 0;  ///< us
  double iterations_mean = 0;
  int iterations_max = 0;
  long periods = 0, deadline_misses = 0, fallback_periods = 0, clipped_periods = 0;
  long tube_exits = 0, state_constraint_violations = 0;
  std::vector<long> tube_exits_per_step;    ///< before the first step, then after each step
  /// Largest distance from the tube in each of those windows, in radii of Z (<= 1:
  /// inside), and the error state that set it most often while outside.
  std::vector<double> tube_ratio_max_per_step;
  /// Seconds from the window's start (mission start, then each step) to the end of
  /// its last period outside the tube: how long the transient lasted (0: no exit).
  std::vector<double> tube_settle_s_per_step;
  std::string tube_worst_state;
  std::array<double, 3> d_hat_final{};     ///< offset-free: the force estimate at the end, N
  std::string solver, plant;
  bool offset_free = false;                 ///< the tube law flown
  bool diverged = false;                    ///< the state became non-finite or left 10x the box
};

MissionMetrics run_mission(const ControllerArtifact& a, const MissionOptions& o);
std::string metrics_json(const MissionMetrics& m);

}  // namespace tmpc
