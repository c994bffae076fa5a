// The plant process (the stand-in for the thesis' Gazebo simulator): the nonlinear
// plant in real time behind the serial protocol. Each period it sends the state frame,
// then holds the newest valid control for one period of plant time. Link loss: with no
// valid control for `hold_s` it stops holding the last input and applies the safe
// command, the hover thrusts of its model with zero servo torques, until controls
// return (counted and timed in its output). The disturbance schedule and the Monte
// Carlo perturbations come from the config; the true tracking error is measured here
// (RMSE), so closed loops over a link are scored by the plant, not by the controller.
// It lives beside the runtime (it is a real-time process over the link), not in sim.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

#include "tmpc/io/protocol.hpp"
#include "tmpc/io/serial_port.hpp"
#include "tmpc/model/config.hpp"

namespace tmpc {

struct PlantLoopOptions {
  std::string plant = "el";
  bool disturbance = true;
  int run = -1;              ///< Monte Carlo run (-1: nominal)
  double duration_s = 80.0;  ///< mission length (0: until `stop`)
  double hold_s = -1.0;      ///< silence before the safe command; < 0: the config's link.plant_hold_s
  std::uint32_t session = 0; ///< this process's session id; 0: drawn at start
};

struct PlantLoopStats {
  long periods = 0, controls = 0, periods_without_control = 0, safe_frames = 0, fallback_frames = 0;
  long held_periods = 0;          ///< periods that held the last input (no control, within hold_s)
  long safe_command_periods = 0;  ///< periods on the plant's own safe command (link lost)
  long link_losses = 0;           ///< times the link was declared lost
  double first_link_loss_s = -1.0;  ///< plant time of the first loss (-1: none)
  std::array<double, 4> last_input{};  ///< the input of the last period (f_r, f_l, tau_r, tau_l)
  std::array<double, 10> rmse{};
  double max_position_error = 0.0;
  bool diverged = false;
  io::LinkCounts link;
  std::uint32_t session = 0, peer_session = 0;
  long controller_sessions = 0;   ///< controller sessions seen (a restart adds one)
  long longest_silence_periods = 0;  ///< longest run of periods without a control, after the first one
  long silent_periods_last_session = 0;  ///< periods without a control since the last session was adopted
  double max_position_error_final_s = 0.0;  ///< over the last second of the run
};

PlantLoopStats run_plant_loop(const Config& cfg, io::Transport& link, const PlantLoopOptions& o,
                              const std::atomic<bool>& stop);

}  // namespace tmpc
