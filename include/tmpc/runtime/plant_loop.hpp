// The plant process (the stand-in for the thesis' Gazebo simulator): the nonlinear
// plant in real time behind the serial protocol. Each period it sends the state frame,
// then holds the newest valid control (the hover input before the first) for one
// period of plant time. The disturbance schedule and the Monte Carlo perturbations
// come from the config; the true tracking error is measured here (RMSE), so closed
// loops over a link are scored by the plant, not by the controller.
#pragma once

#include <array>
#include <atomic>
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
};

struct PlantLoopStats {
  long periods = 0, controls = 0, periods_without_control = 0, safe_frames = 0, fallback_frames = 0;
  std::array<double, 10> rmse{};
  double max_position_error = 0.0;
  bool diverged = false;
  io::DecoderStats link;
};

PlantLoopStats run_plant_loop(const Config& cfg, io::Transport& link, const PlantLoopOptions& o,
                              const std::atomic<bool>& stop);

}  // namespace tmpc
