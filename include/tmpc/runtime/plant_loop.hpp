// The plant process (the stand-in for the thesis' Gazebo simulator): the scenario's
// plant in real time behind the serial protocol. Each period it sends the state frame
// (with the scenario's sensor noise), then holds the newest valid control for one
// period of plant time. Link loss: with no valid control for `hold_s` it stops holding
// the last input and applies the safe command, the hover thrusts of its model with
// zero servo torques (a linear plant: zero), until controls return (counted and timed
// in its output). The disturbances, plant parameters and Monte Carlo draws come from
// the scenario; the true tracking error is measured here (RMSE), so closed loops over
// a link are scored by the plant, not by the controller. It lives beside the runtime
// (it is a real-time process over the link), not in sim.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"
#include "tmpc/model/config.hpp"
#include "tmpc/sim/plant_model.hpp"
#include "tmpc/sim/scenario.hpp"
#include "tmpc/synthesis/artifact.hpp"

namespace tmpc {

/// What the plant process knows of the design: its model, the reference attitude, the
/// period, the link's rules; from a design config (`tmpc plant --config`) or from an
/// artifact's records (`tmpc hil`).
struct PlantSetup {
  PlantModel model;
  ReferenceAttitude attitude = ReferenceAttitude::Trim;
  double sample_time = 0.0;
  LinkSettings link;
  int inputs = 0;
  /// The design's yaw for an any-yaw design (EnvelopeSettings::any_yaw): the plant's
  /// true errors are then taken in the mission reference's yaw frame, as the controller
  /// and `tmpc simulate` take them (x, y along and across the heading); empty: as is.
  std::optional<double> yaw_frame;
  static PlantSetup from_config(const Config& cfg);
  static PlantSetup from_artifact(const ControllerArtifact& a);
};

struct PlantLoopOptions {
  std::string plant;         ///< "" (the scenario's), "el" or "mujoco"
  int run = -1;              ///< Monte Carlo run (-1: none)
  long seed = -1;            ///< its seed (-1: the scenario's)
  double duration_s = -1.0;  ///< mission length (< 0: the scenario's; 0: until `stop`)
  double hold_s = -1.0;      ///< silence before the safe command; < 0: the config's link.plant_hold_s
  std::uint32_t session = 0; ///< this process's session id; 0: drawn at start
  double time_scale = 1.0;   ///< wall-clock seconds per mission second (the controller's, >= 1)
};

struct PlantLoopStats {
  long periods = 0, controls = 0, periods_without_control = 0, safe_frames = 0, fallback_frames = 0;
  long held_periods = 0;          ///< periods that held the last input (no control, within hold_s)
  long safe_command_periods = 0;  ///< periods on the plant's own safe command (link lost)
  long link_losses = 0;           ///< times the link was declared lost
  double first_link_loss_s = -1.0;  ///< plant time of the first loss (-1: none)
  std::vector<double> last_input;   ///< the input of the last period
  std::vector<double> rmse;         ///< per measured state, against the reference
  double max_position_error = 0.0;
  bool diverged = false;
  io::LinkCounts link;
  std::uint32_t session = 0, peer_session = 0;
  long controller_sessions = 0;   ///< controller sessions seen (a restart adds one)
  long longest_silence_periods = 0;  ///< longest run of periods without a control, after the first one
  long silent_periods_last_session = 0;  ///< periods without a control since the last session was adopted
  double max_position_error_final_s = 0.0;  ///< over the last second of the run
};

PlantLoopStats run_plant_loop(const PlantSetup& setup, const Scenario& scenario, io::Transport& link,
                              const PlantLoopOptions& o, const std::atomic<bool>& stop);

}  // namespace tmpc
