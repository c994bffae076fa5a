// The plant's side of the link, scripted for loop tests: one prepared state frame
// per period, delivered once, and every control frame the loop writes taken; a hook
// sees the period count after each control (to switch counters on, or stop the loop).
#pragma once

#include <cstring>
#include <functional>
#include <utility>
#include <vector>

#include "tmpc/io/serial_port.hpp"

namespace tmpc::test {

class ScriptedPlant : public io::Transport {
 public:
  ScriptedPlant(std::vector<std::vector<std::uint8_t>> frames, std::function<void(int)> after_control)
      : frames_(std::move(frames)), after_control_(std::move(after_control)) {}
  long read_some(std::uint8_t* buf, std::size_t cap) override {
    if (delivered_ || period_ >= static_cast<int>(frames_.size())) return 0;
    const std::vector<std::uint8_t>& f = frames_[static_cast<std::size_t>(period_)];
    const std::size_t n = std::min(cap, f.size());
    std::memcpy(buf, f.data(), n);
    delivered_ = true;
    return static_cast<long>(n);
  }
  bool write_all(const std::uint8_t*, std::size_t, int) override {
    ++period_;
    delivered_ = false;
    after_control_(period_);
    return true;
  }
  int controls() const { return period_; }

 private:
  std::vector<std::vector<std::uint8_t>> frames_;
  std::function<void(int)> after_control_;
  int period_ = 0;
  bool delivered_ = false;
};

}  // namespace tmpc::test
