// libFuzzer target of the serial-protocol parser (built when clang is available; see
// tests/io/check_fuzz.cmake). Any byte stream through both decoders must not crash
// (ASan, UBSan), and every frame they accept must be finite, inside the physical
// bounds, and survive an encode-decode round trip unchanged.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "tmpc/io/protocol.hpp"

namespace {

void require(bool ok) {
  if (!ok) __builtin_trap();
}

void check_state(const tmpc::io::StateFrame& f, const tmpc::io::StateBounds& b) {
  require(std::isfinite(f.time) && std::abs(f.time) <= b.time);
  for (double v : f.x) require(std::isfinite(v));
  std::vector<std::uint8_t> wire;
  tmpc::io::encode(f, wire);
  tmpc::io::Decoder d(tmpc::io::FrameType::State, b);
  bool got = false;
  for (std::uint8_t c : wire) got = d.push(c) || got;
  require(got && d.state().seq == f.seq && d.state().time == f.time && d.state().x == f.x);
}

void check_control(const tmpc::io::ControlFrame& f) {
  for (double v : f.u) require(std::isfinite(v));
  std::vector<std::uint8_t> wire;
  tmpc::io::encode(f, wire);
  tmpc::io::Decoder d(tmpc::io::FrameType::Control);
  bool got = false;
  for (std::uint8_t c : wire) got = d.push(c) || got;
  require(got && d.control().seq == f.seq && d.control().u == f.u && d.control().flags == f.flags);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const tmpc::io::StateBounds bounds;
  tmpc::io::Decoder state(tmpc::io::FrameType::State, bounds);
  tmpc::io::Decoder control(tmpc::io::FrameType::Control);
  long delimiters = 0;
  for (std::size_t i = 0; i < size; ++i) {
    delimiters += data[i] == 0;
    if (state.push(data[i])) check_state(state.state(), bounds);
    if (control.push(data[i])) check_control(control.control());
  }
  // A frame ends at a delimiter: never more verdicts than delimiters.
  require(state.stats().accepted + state.stats().rejected() <= delimiters);
  require(control.stats().accepted + control.stats().rejected() <= delimiters);
  // COBS alone: decoding never writes past the buffer it is given.
  std::uint8_t out[64];
  const long n = tmpc::io::cobs_decode(data, size, out, sizeof out);
  require(n <= static_cast<long>(sizeof out));
  return 0;
}
