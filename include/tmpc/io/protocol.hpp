// Serial protocol between the plant (or vehicle) and the controller.
//
// Frame on the wire: COBS(packet) followed by one 0x00 delimiter. Packet, little-endian:
//   u8 version (kProtocolVersion) | u8 type | u32 sequence | payload | u32 CRC-32 of all before
//   type 1 STATE   (plant -> controller): f64 time, f64 x[20]   (q then q', model order)
//   type 2 CONTROL (controller -> plant): f64 u[4] (f_r f_l tau_r tau_l), u8 flags
//        flags: bit 0 fallback law, bit 1 safe command (link silent), bit 2 clipped
// The decoder takes bytes as they come and returns whole, validated frames; a bad
// frame (CRC, length, version, type, NaN/Inf, outside physical bounds, stale or
// repeated sequence, oversize) is counted by reason and dropped, never thrown.
// Sequence gaps (lost frames) are counted; the frame after a gap is accepted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tmpc::io {

constexpr std::uint8_t kProtocolVersion = 1;
constexpr std::size_t kMaxPacket = 256;

enum class FrameType : std::uint8_t { State = 1, Control = 2 };

struct StateFrame {
  std::uint32_t seq = 0;
  double time = 0.0;
  std::array<double, 20> x{};
};

struct ControlFrame {
  std::uint32_t seq = 0;
  std::array<double, 4> u{};
  std::uint8_t flags = 0;
  static constexpr std::uint8_t kFallback = 1, kSafe = 2, kClipped = 4;
};

/// Physical plausibility of a state frame (absolute values).
struct StateBounds {
  double position = 1e4;      ///< m
  double angle = 100.0;       ///< rad (yaw may wind up)
  double velocity = 100.0;    ///< m/s and rad/s
  double time = 1e9;          ///< s
};

/// Encode into `out` (cleared first); returns the number of bytes (delimiter included).
std::size_t encode(const StateFrame& f, std::vector<std::uint8_t>& out);
std::size_t encode(const ControlFrame& f, std::vector<std::uint8_t>& out);

struct DecoderStats {
  long accepted = 0;
  long bad_crc = 0, bad_length = 0, bad_version = 0, unknown_type = 0, non_finite = 0, out_of_bounds = 0;
  long stale_sequence = 0, oversize = 0, bad_cobs = 0;
  long sequence_gaps = 0;  ///< frames lost before an accepted frame
  long rejected() const {
    return bad_crc + bad_length + bad_version + unknown_type + non_finite + out_of_bounds + stale_sequence + oversize +
           bad_cobs;
  }
};

/// Streaming decoder for one direction. Preallocated; push() never allocates or throws.
class Decoder {
 public:
  explicit Decoder(FrameType expected, StateBounds bounds = {});
  /// Feed one byte; returns true when a frame was completed and accepted.
  bool push(std::uint8_t byte);
  const StateFrame& state() const { return state_; }
  const ControlFrame& control() const { return control_; }
  const DecoderStats& stats() const { return stats_; }

 private:
  bool finish();
  FrameType expected_;
  StateBounds bounds_;
  std::array<std::uint8_t, kMaxPacket + kMaxPacket / 254 + 2> raw_{};
  std::array<std::uint8_t, kMaxPacket> packet_{};
  std::size_t n_ = 0;
  bool overflow_ = false;
  bool have_seq_ = false;
  std::uint32_t last_seq_ = 0;
  StateFrame state_, state_next_;
  ControlFrame control_, control_next_;
  DecoderStats stats_;
};

/// COBS (consistent overhead byte stuffing), exposed for tests.
std::size_t cobs_encode(const std::uint8_t* in, std::size_t n, std::uint8_t* out);
/// Returns the decoded length, or -1 for malformed input.
long cobs_decode(const std::uint8_t* in, std::size_t n, std::uint8_t* out, std::size_t cap);

}  // namespace tmpc::io
